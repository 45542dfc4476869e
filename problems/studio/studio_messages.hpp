#pragma once
// The studio's messages: the page posts one JSON object per request and gets one JSON reply,
// with progress objects before it for long computations (problems/studio/http_server.cpp sends
// them as lines of one chunked response). docs/studio.md lists the messages:
//   {"type": "hello"}                       mode, title, the output folder's files
//   {"type": "scene"}                       the body's surface, handles and the current design
//   {"type": "retarget", "targets": [[x, y, z], ...], "sequence": n}   design again (progress,
//                                           then "design"); "sequence" (optional) orders requests
//   {"type": "full_check"}                  the current design solved in full space
//   {"type": "save"}                        report.json and result.vtu into the output folder
// "scene" and "retarget" take "arrays": "float32-base64" for the design's per-triangle E and
// surface displacement as base64 strings of little-endian floats (float32_base64.hpp) instead of
// numbers: the page's form, a third shorter and without decimal formatting.
// A malformed message (not JSON, not an object, an unknown type, a wrong field) gets
// {"type": "error", "message": ...} and changes nothing. Computations run one at a time; a
// retarget that arrives while another runs supersedes it (the older one replies
// {"type": "superseded"}).
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

#include "problems/studio/design_session.hpp"
#include "problems/studio/http_server.hpp"

namespace tailor::studio {

class StudioMessages {
 public:
  // `design`: null for a result viewer. `output_folder`: the one folder whose files are served.
  StudioMessages(std::unique_ptr<DesignSession> design, std::filesystem::path output_folder, std::string title);

  // A retarget's number: its "sequence" when the message has one (the page numbers its
  // requests, so that two sent at once cannot swap places on their way to here), else the next
  // number on arrival. A retarget whose number is below the newest stops at its next iteration
  // (or at once).
  long arrive(long sequence = 0);
  bool is_newest(long request) const { return request >= newest_.load(); }

  using Emit = std::function<void(const nlohmann::json&)>;
  // Handles the message `text`; progress objects go to `emit` (may be empty).
  nlohmann::json handle(const std::string& text, const Emit& emit);

  const std::filesystem::path& output_folder() const { return output_folder_; }

 private:
  nlohmann::json hello() const;
  nlohmann::json scene(bool binary);
  nlohmann::json design_reply(const DesignState& state, bool binary) const;
  nlohmann::json retarget(const nlohmann::json& message, const Emit& emit);
  nlohmann::json full_check();
  nlohmann::json save(const Emit& emit);

  std::unique_ptr<DesignSession> design_;
  std::filesystem::path output_folder_;
  std::string title_;
  std::mutex computing_;  // the design session is used by one request at a time
  std::atomic<long> newest_{0};
};

// The server's endpoints over `messages` (which must outlive the server).
StudioEndpoints endpoints(StudioMessages& messages);

}  // namespace tailor::studio
