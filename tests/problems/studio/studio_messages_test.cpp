// The studio's messages (problems/studio/studio_messages.hpp) on the small handle scene of the
// reduced-design tests: malformed messages get an error and change nothing, a retarget designs
// again, a newer retarget supersedes an older one, the full-space check and save work. The
// reference for "designed": targets that are reachable, the full-space response of known
// designs (as in tests/problems/reduced_design). A drag's design stops once it has settled
// (DesignSession::redesign: the handle error moves by < 0.05% over 5 iterations), so it reaches
// them within 1% reduced and 2% in full space, where the converged loop gets 0.1% and 1%; the
// two targets differ by ~40%, which a stale design would show.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "problems/studio/float32_base64.hpp"
#include "problems/studio/studio_messages.hpp"
#include "tests/problems/reduced_design/small_handle_scene.hpp"
#include "tests/support/temp_folder.hpp"

namespace tailor::studio::studio_messages_test {
namespace fs = std::filesystem;
using json = nlohmann::json;
using tailor::testing::TempFolder;

// The mean tip displacement of the design w = (w0, w1, 0, ...) solved in full space.
json reachable_target(double w0, double w1) {
  const ReducedDesign probe = build_reduced_design(small_handle_scene("stvk"));
  Vector w = Vector::Zero(probe.num_design());
  w[0] = w0;
  w[1] = w1;
  const FullSpaceCheck truth = full_space_check(probe, w);
  EXPECT_TRUE(truth.converged) << truth.message;
  const Vector u = truth.displacement.segment(3 * probe.handles[0].vertices[0], 3);
  return json::array({json::array({u[0], u[1], u[2]})});
}

class StudioDesign : public ::testing::Test {
 protected:
  // The design is built on first use (the precomputation: a fraction of a second here).
  StudioMessages& messages() {
    if (!messages_) {
      auto design = std::make_unique<DesignSession>(small_handle_scene("stvk"));
      messages_ = std::make_unique<StudioMessages>(std::move(design), folder_.str(), "small");
    }
    return *messages_;
  }
  json send(const json& message, std::vector<json>* progress = nullptr) {
    return messages().handle(message.dump(), [&](const json& p) {
      if (progress) progress->push_back(p);
    });
  }
  TempFolder folder_{"studio_messages"};
  std::unique_ptr<StudioMessages> messages_;
};

TEST_F(StudioDesign, SceneDescribesSurfaceAndHandles) {
  const json scene = send({{"type", "scene"}});
  ASSERT_EQ(scene["type"], "scene") << scene.dump();
  // 8 x 2 x 2 cells: the box's surface has 2 (8*2 + 8*2 + 2*2) quads = 72, each two triangles;
  // its vertices are the 9*3*3 grid minus the one interior line of 7 vertices: 74.
  EXPECT_EQ(scene["triangles"].size(), 3u * 144u);
  EXPECT_EQ(scene["positions"].size(), 3u * 74u);
  EXPECT_EQ(scene["youngs_modulus"].size(), 144u);
  EXPECT_EQ(scene["displacement"].size(), 3u * 74u);
  ASSERT_EQ(scene["handles"].size(), 1u);
  EXPECT_FLOAT_EQ(scene["handles"][0]["rest_centre"][0].get<float>(), 5.0f);
  EXPECT_EQ(scene["elements"], 192);
  EXPECT_EQ(send({{"type", "hello"}})["mode"], "design");
}

TEST_F(StudioDesign, MalformedMessagesChangeNothing) {
  const json before = send({{"type", "retarget"}, {"targets", {{0.0, 0.0, -0.1}}}});
  ASSERT_EQ(before["type"], "design") << before.dump();
  const std::vector<std::string> bad = {
      "not json", "[1, 2]", R"({"kind": "scene"})", R"({"type": 5})", R"({"type": "delete_everything"})",
      R"({"type": "retarget"})", R"({"type": "retarget", "targets": [[0, 0]]})",
      R"({"type": "retarget", "targets": [[0, 0, -0.1], [0, 0, -0.1]]})",
      R"({"type": "retarget", "targets": [[0, "a", -0.1]]})", R"({"type": "retarget", "targets": [[0, 0, 0]]})",
      R"({"type": "retarget", "targets": [[0, 0, 1e999]]})", R"({"type": "retarget", "targets": {"0": 1}})",
      R"({"type": "retarget", "targets": [[0, 0, -0.2]], "arrays": "float64"})",
      R"({"type": "scene", "arrays": 32})"};
  for (const std::string& text : bad) {
    const json reply = messages().handle(text, nullptr);
    EXPECT_EQ(reply["type"], "error") << text << " -> " << reply.dump();
    EXPECT_FALSE(reply["message"].get<std::string>().empty());
  }
  const json after = send({{"type", "scene"}});
  EXPECT_EQ(after["targets"], before["targets"]);
  EXPECT_EQ(after["youngs_modulus_range"], before["youngs_modulus_range"]);
}

TEST_F(StudioDesign, RetargetDesignsAgain) {
  std::vector<json> progress;
  const json stiff = reachable_target(-0.4, 0.1), soft = reachable_target(-0.7, 0.1);
  const json first = send({{"type", "retarget"}, {"targets", stiff}}, &progress);
  ASSERT_EQ(first["type"], "design") << first.dump();
  EXPECT_FALSE(progress.empty());
  EXPECT_EQ(progress.front()["type"], "progress");
  EXPECT_LT(first["reduced_errors"][0].get<double>(), 1e-2) << first["message"];
  // A softer design's response: E falls.
  const json second = send({{"type", "retarget"}, {"targets", soft}});
  ASSERT_EQ(second["type"], "design") << second.dump();
  EXPECT_LT(second["reduced_errors"][0].get<double>(), 1e-2) << second["message"];
  EXPECT_LT(second["youngs_modulus_range"][1].get<double>(), first["youngs_modulus_range"][1].get<double>());
  EXPECT_FLOAT_EQ(second["targets"][0][2].get<float>(), soft[0][2].get<float>());
  // The tip's drawn displacement follows: the surface vertex at (5, 0.5, 0.5) moves as the target.
  const json scene = send({{"type", "scene"}});
  double tip_z = 0.0;
  for (std::size_t i = 0; i < scene["positions"].size() / 3; ++i)
    if (scene["positions"][3 * i].get<double>() == 5.0 && scene["positions"][3 * i + 1].get<double>() == 0.5 &&
        scene["positions"][3 * i + 2].get<double>() == 0.5)
      tip_z = scene["displacement"][3 * i + 2].get<double>();
  EXPECT_NEAR(tip_z, soft[0][2].get<double>(), 1e-2 * std::abs(soft[0][2].get<double>()));
}

TEST_F(StudioDesign, NewerRetargetSupersedesOlder) {
  const json start = send({{"type", "retarget"}, {"targets", {{0.0, 0.0, -0.1}}}});
  ASSERT_EQ(start["type"], "design");
  // A newer request arrives while the first runs (at its first progress line).
  const json reply = messages().handle(R"({"type": "retarget", "targets": [[0, 0, -0.3]]})",
                                       [&](const json&) { messages().arrive(); });
  EXPECT_EQ(reply["type"], "superseded") << reply.dump();
  // Numbered requests: one that arrives after a newer one is superseded at once.
  EXPECT_EQ(send({{"type", "retarget"}, {"targets", {{0.0, 0.0, -0.3}}}, {"sequence", 1000}})["type"], "design");
  EXPECT_EQ(send({{"type", "retarget"}, {"targets", {{0.0, 0.0, -0.3}}}, {"sequence", 999}})["type"], "superseded");
  EXPECT_EQ(send({{"type", "retarget"}, {"targets", {{0.0, 0.0, -0.3}}}, {"sequence", -1}})["type"], "error");
  const json restart = send({{"type", "retarget"}, {"targets", start["targets"]}, {"sequence", 1001}});
  ASSERT_EQ(restart["type"], "design");
  const json scene = send({{"type", "scene"}});
  EXPECT_EQ(scene["targets"], start["targets"]);  // the superseded ones left no trace
}

TEST_F(StudioDesign, FullSpaceCheckAndSave) {
  const json target = reachable_target(-0.5, 0.1);
  ASSERT_EQ(send({{"type", "retarget"}, {"targets", target}})["type"], "design");
  const json check = send({{"type", "full_check"}});
  ASSERT_EQ(check["type"], "full_check") << check.dump();
  EXPECT_TRUE(check["converged"].get<bool>());
  EXPECT_LT(check["reduced_errors"][0].get<double>(), 1e-2);
  EXPECT_LT(check["full_errors"][0].get<double>(), 2e-2);
  const json saved = send({{"type", "save"}});
  ASSERT_EQ(saved["type"], "saved") << saved.dump();
  EXPECT_TRUE(fs::exists(fs::path(folder_.str()) / "report.json"));
  EXPECT_TRUE(fs::exists(fs::path(folder_.str()) / "result.vtu"));
  const json report = json::parse(std::ifstream(fs::path(folder_.str()) / "report.json"));
  EXPECT_EQ(report["kind"], "reduced_design");
  EXPECT_LT(report["max_reduced_error"].get<double>(), 1e-3);  // save converges as tailor run
  EXPECT_LT(report["max_full_error"].get<double>(), 1e-2);
  EXPECT_FLOAT_EQ(report["handles"][0]["target_displacement"][2].get<float>(), target[0][2].get<float>());
}

TEST(StudioViewer, DesignMessagesRefusedWithoutAScene) {
  TempFolder folder("studio_viewer");
  StudioMessages messages(nullptr, folder.str(), "viewer");
  EXPECT_EQ(messages.handle(R"({"type": "hello"})", nullptr)["mode"], "results");
  for (const char* type : {"scene", "retarget", "full_check", "save"}) {
    const json reply = messages.handle(json{{"type", type}}.dump(), nullptr);
    EXPECT_EQ(reply["type"], "error") << type;
  }
}

}  // namespace tailor::studio::studio_messages_test

namespace tailor::studio::studio_messages_test {

// The binary form against hand-encoded RFC 4648 base64 of little-endian IEEE floats:
// 1.0f = 0x3F800000 -> bytes 00 00 80 3F -> "AACAPw=="; -2.0f = 0xC0000000 -> "AAAAwA==".
TEST(StudioFloat32Base64, MatchesHandEncodedBytesAndRoundTrips) {
  EXPECT_EQ(encode_float32_base64({1.0f}), "AACAPw==");
  EXPECT_EQ(encode_float32_base64({-2.0f}), "AAAAwA==");
  EXPECT_EQ(encode_float32_base64({1.0f, -2.0f}), "AACAPwAAAMA=");
  EXPECT_EQ(encode_float32_base64({}), "");
  const std::vector<float> values = {0.0f, -0.0f, 3.25e-7f, 1.5e30f, -123.456f, 7.0f, 1.0f / 3.0f};
  for (std::size_t n = 0; n <= values.size(); ++n) {  // every padding length
    const std::vector<float> part(values.begin(), values.begin() + static_cast<long>(n));
    const auto back = decode_float32_base64(encode_float32_base64(part));
    ASSERT_TRUE(back.has_value()) << n;
    ASSERT_EQ(back->size(), n);
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(std::bit_cast<std::uint32_t>((*back)[i]), std::bit_cast<std::uint32_t>(part[i]));
  }
  for (const std::string bad : {"AACAPw=", "AACA Pw==", "AACAP===", "AA==AACA", "AACAPw=A", "AAC"})
    EXPECT_FALSE(decode_float32_base64(bad).has_value()) << bad;
}

TEST_F(StudioDesign, BinaryArraysCarryTheSameNumbers) {
  const json binary = send({{"type", "retarget"}, {"targets", reachable_target(-0.5, 0.1)}, {"arrays", "float32-base64"}});
  ASSERT_EQ(binary["type"], "design") << binary.dump();
  EXPECT_EQ(binary["arrays"], "float32-base64");
  // The current design in both forms: the same floats, bit for bit.
  const json numbers = send({{"type", "scene"}});
  const json scene = send({{"type", "scene"}, {"arrays", "float32-base64"}});
  EXPECT_EQ(numbers["arrays"], "json");
  for (const char* key : {"youngs_modulus", "displacement"}) {
    ASSERT_TRUE(binary[key].is_string()) << key;
    EXPECT_EQ(scene[key], binary[key]) << key;
    const auto decoded = decode_float32_base64(binary[key].get<std::string>());
    ASSERT_TRUE(decoded.has_value()) << key;
    ASSERT_EQ(decoded->size(), numbers[key].size()) << key;
    for (std::size_t i = 0; i < decoded->size(); ++i)
      ASSERT_EQ((*decoded)[i], numbers[key][i].get<float>()) << key << "[" << i << "]";
  }
}

}  // namespace tailor::studio::studio_messages_test
