// Camera paths (demo records, render and demo play): parsing, interpolation, errors, round trip.
#include <cmath>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "scene/camera_path.hpp"
#include <glm/gtc/matrix_transform.hpp>

#include "support/bad_files.hpp"
#include "support/gpu_test_context.hpp"
#include "support/writerless_fifo.hpp"

namespace gt {
namespace {

// Every front end's camera comes from lookAt: eye and target far apart in floats (1e30 and 0)
// gave a NaN view direction and a flat image; a camera that gives no view is refused.
TEST(CameraPath, LookAtGivesAFiniteViewOrRefuses) {
    const scene::Camera far = scene::lookAt({1e30f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0f);
    EXPECT_NEAR(far.forward.x, -1.0f, 1e-6f);
    EXPECT_TRUE(std::isfinite(far.forward.y) && std::isfinite(far.forward.z));
    const float nan = std::nanf("");
    EXPECT_THROW((void)scene::lookAt({1, 2, 3}, {1, 2, 3}, 1.0f), ArgumentError);
    EXPECT_THROW((void)scene::lookAt({nan, 0, 0}, {0, 0, 1}, 1.0f), ArgumentError);
    EXPECT_THROW((void)scene::lookAt({0, 0, 0}, {0, 0, 1}, nan), ArgumentError);
    // 1e30 + 1 is 1e30 in floats: the same point.
    EXPECT_THROW((void)scene::lookAt({1e30f, 0, 0}, {1e30f + 1.0f, 0, 0}, 1.0f), ArgumentError);
}

TEST(CameraPath, InterpolatesClampsAndRoundTrips) {
    const auto dir = test::tempDir("camera_path");
    const auto file = dir / "path.csv";
    {
        std::ofstream out(file);
        out << "# recorded\nt_ms,ex,ey,ez,tx,ty,tz\n0,0,1,0,0,1,-1\n100,2,1,0,2,1,-1\n";
    }
    const scene::CameraPath p = scene::CameraPath::load(file);
    const scene::Camera mid = p.at(50.0, 1.0f);
    EXPECT_NEAR(mid.position.x, 1.0f, 1e-6f);
    EXPECT_NEAR(mid.forward.z, -1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(mid.yfov, 1.0f);
    EXPECT_NEAR(p.at(-10.0, 1.0f).position.x, 0.0f, 1e-6f); // clamped at both ends
    EXPECT_NEAR(p.at(500.0, 1.0f).position.x, 2.0f, 1e-6f);
    const auto copy = dir / "copy.csv";
    p.save(copy);
    const scene::CameraPath q = scene::CameraPath::load(copy);
    ASSERT_EQ(q.keys().size(), 2u);
    EXPECT_NEAR(q.at(50.0, 1.0f).position.x, 1.0f, 1e-5f);
    EXPECT_FALSE(std::filesystem::exists(dir / "copy.csv.tmp"));
}

TEST(CameraPath, RefusesWhatItCannotPlay) {
    const auto dir = test::tempDir("camera_path_bad");
    auto expectBad = [&](const std::string& body, const std::string& mention) {
        test::expectLoadError(dir / "bad.csv", body, mention, [](const std::filesystem::path& f) {
            (void)scene::CameraPath::load(f);
        });
    };
    expectBad("t_ms,x,y\n0,1,2\n", "header");
    expectBad("t_ms,ex,ey,ez,tx,ty,tz\n0,1,2,3,4,5\n", "seven numbers");
    expectBad("t_ms,ex,ey,ez,tx,ty,tz\n0,1,1,1,1,1,1\n", "eye on its target");
    expectBad("t_ms,ex,ey,ez,tx,ty,tz\n5,0,0,0,0,0,1\n5,0,0,0,0,0,1\n", "increase");
    expectBad("t_ms,ex,ey,ez,tx,ty,tz\n0,nan,0,0,0,0,1\n", "bad.csv:2: ex nan is not a finite");
    expectBad("", "empty");
    EXPECT_THROW((void)scene::CameraPath::load(dir), LoadError); // a folder
}

// 1e300 is a finite double but an infinite float: the camera became NaN and the run rendered a
// flat image with exit 0. Every value names its line and itself.
TEST(CameraPath, ValuesOutOfRangeNameTheLineAndTheValue) {
    const auto dir = test::tempDir("camera_path_range");
    auto expectBad = [&](const std::string& body, const std::string& mention) {
        test::expectLoadError(dir / "far.csv", body, mention, [](const std::filesystem::path& f) {
            (void)scene::CameraPath::load(f);
        });
    };
    const std::string header = "t_ms,ex,ey,ez,tx,ty,tz\n0,0,0,0,0,0,1\n";
    expectBad(header + "10,1e300,0,0,0,0,1\n", "far.csv:3: ex 1e300 is not a finite number");
    expectBad(header + "10,0,0,0,0,0,-2e6\n", "far.csv:3: tz -2e6");
    expectBad(header + "1e300,0,0,0,0,0,1\n", "far.csv:3: t_ms 1e300");
    expectBad(header + "10,0,0,0,0,0,1e999\n", "far.csv:3: tz 1e999");
    expectBad(header + "10,0,inf,0,0,0,1\n", "far.csv:3: ey inf");
    // Keys built in memory (the demo's recorder) are held to the same bounds.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW((void)scene::CameraPath::fromKeys({{0.0, glm::vec3(nan), glm::vec3(1.0f)}}),
                 LoadError);
    EXPECT_THROW(
        (void)scene::CameraPath::fromKeys({{1e300, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f)}}),
        LoadError);
    // The bounds leave every real path alone.
    expectBad(header + "10,999999,0,0,0,0,1\n5,0,0,0,0,0,1\n", "increase");
}

// A FIFO blocked the loader forever; a device (/dev/zero grew to 4 GB) is refused by kind.
TEST(CameraPath, FifosAndDevicesAreRefusedWithoutReading) {
    const auto dir = test::tempDir("camera_path_kinds");
    const test::WriterlessFifo fifo(dir / "path.csv");
    const std::string e =
        test::thrownMessage<LoadError>([&] { (void)scene::CameraPath::load(fifo.path()); });
    EXPECT_NE(e.find(fifo.path().string() + ": a FIFO"), std::string::npos) << e;
    EXPECT_FALSE(fifo.blockedALoader());
    std::filesystem::create_symlink("/dev/zero", dir / "device.csv");
    const std::string d =
        test::thrownMessage<LoadError>([&] { (void)scene::CameraPath::load(dir / "device.csv"); });
    EXPECT_NE(d.find("device.csv: a character device"), std::string::npos) << d;
}

} // namespace
} // namespace gt

#include "scene/bvh.hpp"
#include "scene/start_view.hpp"

namespace gt {
namespace {

// A closed room 12 x 3 x 4 (long along x): the start is inside, at eye height, looking along x;
// an open scene (a floor only) keeps the framing from outside.
TEST(StartView, InsideAnEnclosedRoomAtEyeHeightLookingDownItsLength) {
    scene::Scene room;
    scene::SceneBuilder b(room);
    const uint32_t m = b.material({});
    b.box(glm::scale(glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 1.5f, 0.0f)),
                     glm::vec3(12.0f, 3.0f, 4.0f)),
          m);
    const scene::Bvh bvh(room);
    const auto v = scene::insideStartView(room, bvh);
    ASSERT_TRUE(v.has_value());
    EXPECT_NEAR(v->position.y, 1.6f, 1e-3f);
    EXPECT_NEAR(v->position.x, 3.0f, 1e-3f);
    EXPECT_GT(std::abs(glm::normalize(v->forward).x), 0.99f); // down the room's length
    scene::Scene open;
    scene::SceneBuilder ob(open);
    ob.quad({-5, 0, -5}, {10, 0, 0}, {0, 0, 10}, ob.material({}));
    const scene::Bvh obvh(open);
    EXPECT_FALSE(scene::insideStartView(open, obvh).has_value());
}

} // namespace
} // namespace gt
