// The studio's message channel: one POST per message to api/message (relative to the page, whose
// URL carries the token), answered by lines of JSON: progress objects, then the reply. `timing`
// (optional) receives where the time went, in ms from the call: headers (the response's start),
// body (its last byte), and parse_ms (JSON.parse of the reply line) with the reply's bytes.
export async function send(message, onProgress, timing) {
  const start = performance.now();
  const response = await fetch('api/message', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(message),
  });
  if (!response.ok) throw new Error(`${response.status}: ${await response.text()}`);
  if (timing) timing.headers = performance.now() - start;
  const reader = response.body.getReader();
  const decoder = new TextDecoder();
  let buffer = '';
  let last = null;
  for (;;) {
    const { value, done } = await reader.read();
    if (value) buffer += decoder.decode(value, { stream: true });
    let newline;
    while ((newline = buffer.indexOf('\n')) >= 0) {
      const line = buffer.slice(0, newline);
      buffer = buffer.slice(newline + 1);
      if (!line) continue;
      const parsing = performance.now();
      const object = JSON.parse(line);
      if (timing && object.type !== 'progress') {
        timing.parse_ms = performance.now() - parsing;
        timing.bytes = line.length;
      }
      if (object.type === 'progress' && onProgress) onProgress(object);
      else last = object;
    }
    if (done) break;
  }
  if (timing) timing.body = performance.now() - start;
  if (!last) throw new Error('no reply');
  return last;
}

// A file of the output folder, as text.
export async function fetchFile(path) {
  const response = await fetch('files/' + path.split('/').map(encodeURIComponent).join('/'));
  if (!response.ok) throw new Error(`${path}: ${response.status}`);
  return response.text();
}

// An array of a reply: numbers as they are, or a base64 string of little-endian IEEE floats
// (the "float32-base64" form) as a Float32Array.
export function float32Array(value) {
  if (typeof value !== 'string') return value;
  const text = atob(value);
  const bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
  const view = new DataView(bytes.buffer);
  const out = new Float32Array(bytes.length / 4);
  for (let i = 0; i < out.length; ++i) out[i] = view.getFloat32(4 * i, true);
  return out;
}
