#pragma once
// The studio's HTTP server (cpp-httplib): the page's assets, the one output folder's files and
// the messages (problems/studio/studio_messages.hpp), each request checked by
// problems/studio/request_guard.hpp and every file path by problems/studio/served_path.hpp.
// URLs: /<token>/ (the page), /<token>/assets/<file>, /<token>/files/<file>,
// POST /<token>/api/message (a chunked response: progress lines, then the reply, one JSON
// object per line).
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace tailor::studio {

// What the server answers with, kept free of the design's types so that this file and the one
// that includes cpp-httplib stay small (studio_messages.hpp's endpoints() fills it).
struct StudioEndpoints {
  std::filesystem::path output_folder;  // the one folder whose files are served
  // Handles one message (JSON text); each progress line goes to `emit`. Returns the reply's text.
  std::function<std::string(const std::string& text, const std::function<void(const std::string&)>& emit)> handle;
};

struct StudioServerOptions {
  std::string address = "127.0.0.1";  // loopback only; the Host check accepts loopback names alone
  int port = 0;                        // 0: a free port
  std::filesystem::path assets;        // the built page (index.html and its modules)
  std::string token;                   // empty: a random one
};

class StudioServer {
 public:
  StudioServer(StudioEndpoints endpoints, StudioServerOptions options);
  ~StudioServer();
  StudioServer(const StudioServer&) = delete;
  StudioServer& operator=(const StudioServer&) = delete;

  // Binds the socket (throws std::runtime_error when it cannot) and returns the port.
  int bind();
  std::string url() const;  // http://127.0.0.1:<port>/<token>/
  const std::string& token() const;
  void serve();  // answers requests until stop() (after bind())
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tailor::studio
