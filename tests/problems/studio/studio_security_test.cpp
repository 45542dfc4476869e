// The studio server's security model (problems/studio/request_guard.hpp, served_path.hpp,
// http_server.hpp): the token, the Host and Origin checks and every path-traversal case, first
// as pure functions, then through a real server on a loopback port with cpp-httplib's client.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "problems/studio/http_server.hpp"
#include "problems/studio/request_guard.hpp"
#include "problems/studio/served_path.hpp"
#include "problems/studio/studio_messages.hpp"
#include "tests/support/temp_folder.hpp"
// Last: it includes <resolv.h>, whose macro _res renames a parameter of Eigen's templates.
#include <httplib.h>

namespace tailor::studio::studio_security_test {
namespace fs = std::filesystem;
using tailor::testing::TempFolder;

void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

TEST(StudioGuard, TokenIsRandomHexAndComparedWhole) {
  const std::string a = random_token(), b = random_token();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_NE(a, b);
  EXPECT_EQ(a.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_TRUE(constant_time_equal(a, a));
  EXPECT_FALSE(constant_time_equal(a, a.substr(0, 31)));  // a prefix is not the token
  std::string flipped = a;
  flipped.back() = flipped.back() == '0' ? '1' : '0';
  EXPECT_FALSE(constant_time_equal(a, flipped));
  std::string rest;
  EXPECT_TRUE(strip_token("/" + a + "/files/report.json", a, rest));
  EXPECT_EQ(rest, "files/report.json");
  EXPECT_TRUE(strip_token("/" + a, a, rest));
  EXPECT_EQ(rest, "");
  EXPECT_FALSE(strip_token("/files/report.json", a, rest));
  EXPECT_FALSE(strip_token("/" + a.substr(0, 31) + "/files/report.json", a, rest));
  EXPECT_FALSE(strip_token("/" + a + "x/", a, rest));
  EXPECT_FALSE(strip_token("//" + a + "/", a, rest));
  EXPECT_FALSE(strip_token("/x/", "", rest));  // an empty token never matches
}

TEST(StudioGuard, HostMustBeLoopbackWithThePort) {
  EXPECT_TRUE(is_loopback_host("127.0.0.1:8123", 8123));
  EXPECT_TRUE(is_loopback_host("localhost:8123", 8123));
  EXPECT_TRUE(is_loopback_host("[::1]:8123", 8123));
  EXPECT_FALSE(is_loopback_host("127.0.0.1:8124", 8123));
  EXPECT_FALSE(is_loopback_host("127.0.0.1", 8123));
  EXPECT_FALSE(is_loopback_host("evil.example:8123", 8123));  // DNS rebinding
  EXPECT_FALSE(is_loopback_host("127.0.0.1.evil.example:8123", 8123));
  EXPECT_FALSE(is_loopback_host("192.168.1.5:8123", 8123));
  EXPECT_FALSE(is_loopback_host("127.0.0.1:8123x", 8123));
  EXPECT_FALSE(is_loopback_host("", 8123));
}

TEST(StudioGuard, CrossOriginRefused) {
  EXPECT_EQ(refuse_headers({"127.0.0.1:9000", "", ""}, 9000), "");
  EXPECT_EQ(refuse_headers({"127.0.0.1:9000", "http://127.0.0.1:9000", "same-origin"}, 9000), "");
  EXPECT_NE(refuse_headers({"127.0.0.1:9000", "http://evil.example", ""}, 9000), "");
  EXPECT_NE(refuse_headers({"127.0.0.1:9000", "http://127.0.0.1:9001", ""}, 9000), "");  // another local server
  EXPECT_NE(refuse_headers({"127.0.0.1:9000", "https://127.0.0.1:9000", ""}, 9000), "");
  EXPECT_NE(refuse_headers({"127.0.0.1:9000", "null", ""}, 9000), "");  // a sandboxed or file: page
  EXPECT_NE(refuse_headers({"127.0.0.1:9000", "", "cross-site"}, 9000), "");
  EXPECT_NE(refuse_headers({"evil.example:9000", "", ""}, 9000), "");
}

class ServedFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    write_file(root_path() / "report.json", "{}");
    write_file(root_path() / "frames" / "f_0001.vtu", "<VTKFile/>");
    write_file(outside_path() / "secret.txt", "secret");
    fs::create_symlink(outside_path() / "secret.txt", root_path() / "link_out.txt");
    fs::create_symlink(outside_path(), root_path() / "dir_out");
    fs::create_symlink(root_path() / "report.json", root_path() / "link_in.json");
  }
  fs::path root_path() const { return fs::path(folder_.str()) / "served"; }
  fs::path outside_path() const { return fs::path(folder_.str()) / "outside"; }
  TempFolder folder_{"studio_paths"};
};

TEST_F(ServedFolder, FilesInsideAreServed) {
  ServedPath p = resolve_served_path(root_path(), "report.json");
  ASSERT_TRUE(p.file) << p.reason;
  EXPECT_EQ(p.file->filename(), "report.json");
  EXPECT_TRUE(resolve_served_path(root_path(), "frames/f_0001.vtu").file);
  EXPECT_TRUE(resolve_served_path(root_path(), "link_in.json").file);  // a link that stays inside
  EXPECT_EQ(resolve_served_path(root_path(), "missing.json").status, 404);
  EXPECT_EQ(content_type("a/b.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(content_type("a/b.vtu"), "application/xml");
}

TEST_F(ServedFolder, DotDotRefused) {
  for (const std::string path : {"../outside/secret.txt", "frames/../../outside/secret.txt", "..", "frames/..",
                                 "frames/../report.json"}) {
    const ServedPath p = resolve_served_path(root_path(), path);
    EXPECT_FALSE(p.file) << path;
    EXPECT_EQ(p.status, 400) << path;
  }
}

TEST_F(ServedFolder, AbsoluteAndOddPathsRefused) {
  const std::string absolute = (outside_path() / "secret.txt").string();
  EXPECT_FALSE(resolve_served_path(root_path(), absolute).file);
  EXPECT_EQ(resolve_served_path(root_path(), absolute).status, 400);
  EXPECT_FALSE(resolve_served_path(root_path(), "/etc/passwd").file);
  EXPECT_FALSE(resolve_served_path(root_path(), "..\\outside\\secret.txt").file);
  EXPECT_FALSE(resolve_served_path(root_path(), "./report.json").file);
  EXPECT_FALSE(resolve_served_path(root_path(), "frames//f_0001.vtu").file);
  EXPECT_FALSE(resolve_served_path(root_path(), std::string("report.json\0.png", 16)).file);
  EXPECT_FALSE(resolve_served_path(root_path(), "frames").file);  // a folder is not a file
  EXPECT_FALSE(resolve_served_path(root_path(), "").file);
}

TEST_F(ServedFolder, SymlinksOutRefused) {
  const ServedPath file_link = resolve_served_path(root_path(), "link_out.txt");
  EXPECT_FALSE(file_link.file);
  EXPECT_EQ(file_link.status, 400);
  const ServedPath dir_link = resolve_served_path(root_path(), "dir_out/secret.txt");
  EXPECT_FALSE(dir_link.file);
  EXPECT_EQ(dir_link.status, 400);
  // The served folder itself reached through a link is fine: only where the file resolves counts.
  fs::create_symlink(root_path(), fs::path(folder_.str()) / "served_link");
  EXPECT_TRUE(resolve_served_path(fs::path(folder_.str()) / "served_link", "report.json").file);
  EXPECT_FALSE(resolve_served_path(fs::path(folder_.str()) / "served_link", "link_out.txt").file);
  // A sibling folder whose name starts like the served one is outside it.
  write_file(fs::path(folder_.str()) / "served2" / "x.json", "{}");
  fs::create_symlink(fs::path(folder_.str()) / "served2" / "x.json", root_path() / "sibling.json");
  EXPECT_FALSE(resolve_served_path(root_path(), "sibling.json").file);
}

// A real server on a free loopback port, with a result-viewer session over the served folder.
class StudioHttp : public ServedFolder {
 protected:
  void SetUp() override {
    ServedFolder::SetUp();
    write_file(assets_path() / "index.html", "<!doctype html><title>studio</title>");
    messages_ = std::make_unique<StudioMessages>(nullptr, root_path(), "test");
    StudioServerOptions options;
    options.assets = assets_path();
    server_ = std::make_unique<StudioServer>(endpoints(*messages_), options);
    port_ = server_->bind();
    thread_ = std::thread([this] { server_->serve(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
  }
  void TearDown() override {
    server_->stop();
    thread_.join();
  }
  fs::path assets_path() const { return fs::path(folder_.str()) / "assets"; }
  std::string prefix() const { return "/" + server_->token() + "/"; }
  int get_status(const std::string& path, const httplib::Headers& headers = {}) {
    const auto result = client_->Get(path.c_str(), headers);
    return result ? result->status : -1;
  }

  std::unique_ptr<StudioMessages> messages_;
  std::unique_ptr<StudioServer> server_;
  int port_ = 0;
  std::thread thread_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(StudioHttp, TokenRequired) {
  EXPECT_EQ(server_->url(), "http://127.0.0.1:" + std::to_string(port_) + prefix());
  EXPECT_EQ(get_status(prefix()), 200);
  EXPECT_EQ(get_status(prefix() + "files/report.json"), 200);
  EXPECT_EQ(get_status("/"), 403);
  EXPECT_EQ(get_status("/files/report.json"), 403);
  EXPECT_EQ(get_status("/" + random_token() + "/files/report.json"), 403);
  const auto post = client_->Post("/api/message", R"({"type": "hello"})", "application/json");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 403);
  const auto hello = client_->Post((prefix() + "api/message").c_str(), R"({"type": "hello"})", "application/json");
  ASSERT_TRUE(hello);
  EXPECT_EQ(hello->status, 200);
  const auto reply = nlohmann::json::parse(hello->body);
  EXPECT_EQ(reply["mode"], "results");
  EXPECT_GE(reply["files"].size(), 2u);
}

TEST_F(StudioHttp, HostAndOriginChecked) {
  EXPECT_EQ(get_status(prefix(), {{"Host", "evil.example:" + std::to_string(port_)}}), 403);
  EXPECT_EQ(get_status(prefix(), {{"Host", "127.0.0.1:1"}}), 403);
  EXPECT_EQ(get_status(prefix(), {{"Origin", "http://evil.example"}}), 403);
  EXPECT_EQ(get_status(prefix(), {{"Origin", "http://127.0.0.1:" + std::to_string(port_)}}), 200);
  EXPECT_EQ(get_status(prefix(), {{"Sec-Fetch-Site", "cross-site"}}), 403);
  const auto post = client_->Post((prefix() + "api/message").c_str(), {{"Origin", "http://evil.example"}},
                                  R"({"type": "hello"})", "application/json");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 403);
}

TEST_F(StudioHttp, TraversalRefusedOverHttp) {
  EXPECT_EQ(get_status(prefix() + "files/../outside/secret.txt"), 400);
  EXPECT_EQ(get_status(prefix() + "files/%2e%2e/outside/secret.txt"), 400);  // decoded, then checked
  EXPECT_EQ(get_status(prefix() + "files/%2E%2E%2Foutside%2Fsecret.txt"), 400);
  EXPECT_EQ(get_status(prefix() + "files/link_out.txt"), 400);
  EXPECT_EQ(get_status(prefix() + "files/dir_out/secret.txt"), 400);
  EXPECT_EQ(get_status(prefix() + "files//etc/passwd"), 400);
  EXPECT_EQ(get_status(prefix() + "assets/../served/report.json"), 400);
  EXPECT_EQ(get_status(prefix() + "elsewhere/report.json"), 404);
  const auto secret = client_->Get((prefix() + "files/link_out.txt").c_str());
  ASSERT_TRUE(secret);
  EXPECT_EQ(secret->body.find("secret"), std::string::npos);
}

}  // namespace tailor::studio::studio_security_test
