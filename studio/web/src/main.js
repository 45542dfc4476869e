// tailor studio's page: asks the server what it serves (a handle scene to design, or an output
// folder to view) and starts that view. window.studio exposes the state for the browser tests.
import { send } from './api.js';
import { Viewer } from './viewer.js';
import { DesignView, ARRAYS } from './design.js';
import { ResultViewer } from './results.js';

const statusBox = document.getElementById('status');
const status = (text) => (statusBox.textContent = text);

async function start() {
  const viewer = new Viewer(document.getElementById('view'));
  const hello = await send({ type: 'hello' });
  document.getElementById('title').textContent = `tailor studio: ${hello.title}`;
  window.studio = { mode: hello.mode, viewer, ready: false };
  if (hello.mode === 'design') {
    status('loading the scene...');
    const scene = await send({ type: 'scene', arrays: ARRAYS });
    if (scene.type !== 'scene') throw new Error(scene.message);
    window.studio.design = new DesignView(viewer, scene, status);
    await window.studio.design.retarget(null); // the design for the scene's own targets
  } else {
    window.studio.results = new ResultViewer(viewer, hello.files, status);
    await window.studio.results.start();
  }
  await viewer.renderedFrame();
  window.studio.ready = true;
}

start().catch((error) => {
  status(`error: ${error.message}`);
  window.studio = { ...(window.studio || {}), error: error.message };
});
