// The one translation unit that includes cpp-httplib (Debian's build: declarations here, the
// implementation in libcpp-httplib.so).
#include "problems/studio/http_server.hpp"

#include <algorithm>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "problems/studio/request_guard.hpp"
#include "problems/studio/served_path.hpp"
// Last: it includes <resolv.h>, whose macro _res renames a parameter of Eigen's templates.
#include <httplib.h>

namespace tailor::studio {

struct StudioServer::Impl {
  StudioEndpoints endpoints;
  StudioServerOptions options;
  httplib::Server server;
  int port = 0;

  Impl(StudioEndpoints e, StudioServerOptions o) : endpoints(std::move(e)), options(std::move(o)) {
    if (options.token.empty()) options.token = random_token();
    server.set_payload_max_length(1 << 20);  // messages are small
    // A reply ends with small writes (the last chunk, the terminating one): with Nagle's
    // algorithm they wait for the ACK of the data before them, which the page's side delays by
    // up to 40 ms on Linux. Replies are written whole, so no tiny packets come of this.
    server.set_tcp_nodelay(true);
    server.set_default_headers({{"Cache-Control", "no-store"},
                                {"X-Content-Type-Options", "nosniff"},
                                {"Referrer-Policy", "no-referrer"},
                                {"Content-Security-Policy", "default-src 'self'; style-src 'self' 'unsafe-inline'"}});
    // Every request, whatever its method, passes the guard first.
    server.set_pre_routing_handler([this](const httplib::Request& request, httplib::Response& response) {
      const RequestHeaders headers{request.get_header_value("Host"), request.get_header_value("Origin"),
                                   request.get_header_value("Sec-Fetch-Site")};
      std::string reason = refuse_headers(headers, port);
      std::string rest;
      if (reason.empty() && !strip_token(request.path, options.token, rest)) reason = "no valid token in the path";
      if (reason.empty()) return httplib::Server::HandlerResponse::Unhandled;
      response.status = 403;
      response.set_content("refused: " + reason + "\n", "text/plain; charset=utf-8");
      return httplib::Server::HandlerResponse::Handled;
    });
    server.Get(".*", [this](const httplib::Request& request, httplib::Response& response) {
      std::string rest;
      strip_token(request.path, options.token, rest);
      if (rest.empty()) rest = "assets/index.html";
      if (request.path.find('/', 1) == std::string::npos) {  // "/<token>": relative URLs need the slash
        response.status = 302;
        response.set_header("Location", request.path + "/");
        return;
      }
      std::filesystem::path root;
      std::string below;
      if (rest.rfind("assets/", 0) == 0) {
        root = options.assets;
        below = rest.substr(7);
      } else if (rest.rfind("files/", 0) == 0) {
        root = endpoints.output_folder;
        below = rest.substr(6);
      } else {
        response.status = 404;
        response.set_content("no such page\n", "text/plain; charset=utf-8");
        return;
      }
      const ServedPath served = resolve_served_path(root, below);
      if (!served.file) {
        response.status = served.status;
        response.set_content("refused: " + served.reason + "\n", "text/plain; charset=utf-8");
        return;
      }
      // Streamed in pieces: frame series and large results are megabytes.
      auto file = std::make_shared<std::ifstream>(*served.file, std::ios::binary);
      const auto size = static_cast<std::size_t>(std::filesystem::file_size(*served.file));
      response.set_content_provider(size, content_type(*served.file),
                                    [file](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                                      std::vector<char> piece(std::min<std::size_t>(length, 1 << 16));
                                      file->seekg(static_cast<std::streamoff>(offset));
                                      file->read(piece.data(), static_cast<std::streamsize>(piece.size()));
                                      return file->gcount() > 0 &&
                                             sink.write(piece.data(), static_cast<std::size_t>(file->gcount()));
                                    });
    });
    server.Post(".*", [this](const httplib::Request& request, httplib::Response& response) {
      std::string rest;
      strip_token(request.path, options.token, rest);
      if (rest != "api/message") {
        response.status = 404;
        response.set_content("no such endpoint\n", "text/plain; charset=utf-8");
        return;
      }
      // The computation runs while the response streams: progress lines, then the reply.
      response.set_chunked_content_provider(
          "application/x-ndjson", [this, body = request.body](std::size_t, httplib::DataSink& sink) {
            const auto emit = [&sink](const std::string& text) {
              const std::string line = text + "\n";
              sink.write(line.data(), line.size());
            };
            emit(endpoints.handle(body, emit));
            sink.done();
            return true;
          });
    });
  }
};

StudioServer::StudioServer(StudioEndpoints endpoints, StudioServerOptions options)
    : impl_(std::make_unique<Impl>(std::move(endpoints), std::move(options))) {}

StudioServer::~StudioServer() { stop(); }

int StudioServer::bind() {
  Impl& s = *impl_;
  if (s.options.port == 0) {
    s.port = s.server.bind_to_any_port(s.options.address);
  } else {
    s.port = s.server.bind_to_port(s.options.address, s.options.port) ? s.options.port : -1;
  }
  if (s.port <= 0)
    throw std::runtime_error("tailor studio: cannot listen on " + s.options.address +
                             (s.options.port ? ":" + std::to_string(s.options.port) : std::string(" (any port)")));
  return s.port;
}

std::string StudioServer::url() const {
  return "http://" + impl_->options.address + ":" + std::to_string(impl_->port) + "/" + impl_->options.token + "/";
}

const std::string& StudioServer::token() const { return impl_->options.token; }

void StudioServer::serve() { impl_->server.listen_after_bind(); }

void StudioServer::stop() {
  if (impl_->server.is_running()) impl_->server.stop();
}

}  // namespace tailor::studio
