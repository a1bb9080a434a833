#include <fstream>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "foveation/gaze_trace.hpp"
#include "support/bad_files.hpp"
#include "support/gpu_test_context.hpp"
#include "support/writerless_fifo.hpp"

namespace gt::foveation {
namespace {

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto p = test::tempDir("trace") / name;
    std::ofstream(p) << text;
    return p;
}

TEST(GazeTrace, ParsesAndInterpolates) {
    const GazeTrace t =
        GazeTrace::load(write("a.csv", "# comment\nt_ms,x,y\n0,10,20\n10,30,40\r\n"));
    ASSERT_EQ(t.samples().size(), 2u);
    EXPECT_EQ(t.at(5.0), glm::vec2(20.0f, 30.0f));
    EXPECT_EQ(t.at(-1.0), glm::vec2(10.0f, 20.0f));
    EXPECT_EQ(t.at(99.0), glm::vec2(30.0f, 40.0f));
}

// Found by fuzzing: each eye's times increase, but the rows of the two eyes interleave, so the
// file's first and last rows are not the trace's start and end.
TEST(GazeTrace, PerEyeRowsOutOfOrderAcrossEyes) {
    const GazeTrace t =
        GazeTrace::load(write("eyes.csv", "t_ms,yaw_deg,pitch_deg,eye\n20,1,1,left\n5,-1,1,right\n"
                                          "30,2,2,left\n10,-2,2,right\n"));
    EXPECT_EQ(t.startMs(), 5.0);
    EXPECT_EQ(t.endMs(), 30.0);
}

TEST(GazeTrace, MalformedFilesNameFileAndLine) {
    auto error = [](const std::filesystem::path& p) {
        try {
            (void)GazeTrace::load(p);
        } catch (const LoadError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(error(write("h.csv", "time,x,y\n0,1,2\n")).find("h.csv:1"), std::string::npos);
    EXPECT_NE(error(write("n.csv", "t_ms,x,y\n0,1,2\n5,abc,2\n")).find("n.csv:3"),
              std::string::npos);
    EXPECT_NE(error(write("o.csv", "t_ms,x,y\n5,1,2\n5,1,2\n")).find("must increase"),
              std::string::npos);
    EXPECT_NE(error(write("e.csv", "t_ms,x,y\n")).find("no samples"), std::string::npos);
    // A fuzz regression case: 1e300 pixels became an infinite float gaze.
    EXPECT_NE(error(write("far.csv", "t_ms,x,y\n0,1e300,5\n")).find("far.csv:2: gaze pixels"),
              std::string::npos);
    EXPECT_NE(error("/nonexistent/trace.csv").find("/nonexistent/trace.csv"), std::string::npos);
}

// A time of 1e300 ms loaded and overflowed the frame count derived from it; angles and pixels
// out of range name the values that are.
TEST(GazeTrace, ValuesOutOfRangeNameTheLineAndTheValue) {
    auto error = [](const std::filesystem::path& p) {
        return test::thrownMessage<LoadError>([&] { (void)GazeTrace::load(p); });
    };
    EXPECT_NE(error(write("t.csv", "t_ms,x,y\n0,1,2\n1e300,1,2\n")).find("t.csv:3: t_ms 1e300"),
              std::string::npos);
    EXPECT_NE(error(write("n.csv", "t_ms,x,y\n0,nan,2\n")).find("n.csv:2: 'nan' is not a finite"),
              std::string::npos);
    EXPECT_NE(error(write("a.csv", "t_ms,yaw_deg,pitch_deg\n0,95,2\n")).find("got 95, 2"),
              std::string::npos);
    EXPECT_NE(error(write("p.csv", "t_ms,x,y\n0,1,-3e6\n")).find("got 1, -3e6"), std::string::npos);
}

// A FIFO blocked the loader forever; a device (/dev/zero grew to 4 GB) is refused by kind.
TEST(GazeTrace, FifosAndDevicesAreRefusedWithoutReading) {
    const auto dir = test::tempDir("trace_kinds");
    const test::WriterlessFifo fifo(dir / "gaze.csv");
    const std::string e =
        test::thrownMessage<LoadError>([&] { (void)GazeTrace::load(fifo.path()); });
    EXPECT_NE(e.find(fifo.path().string() + ": a FIFO"), std::string::npos) << e;
    EXPECT_FALSE(fifo.blockedALoader());
    std::filesystem::create_symlink("/dev/zero", dir / "device.csv");
    const std::string d =
        test::thrownMessage<LoadError>([&] { (void)GazeTrace::load(dir / "device.csv"); });
    EXPECT_NE(d.find("device.csv: a character device"), std::string::npos) << d;
}

TEST(GazeTrace, ShippedTracesLoad) {
    struct Shipped {
        const char* name;
        float width, height; // the eye image its pixels are in
    };
    for (const Shipped& sh :
         {Shipped{"fixations", 1280, 1440}, Shipped{"saccade", 1280, 1440},
          Shipped{"pursuit", 1280, 1440}, Shipped{"pursuit_640x720", 640, 720}}) {
        const auto p = std::filesystem::path(GT_SOURCE_DIR) / "content" / "gaze" /
                       (std::string(sh.name) + ".csv");
        const GazeTrace t = GazeTrace::load(p);
        EXPECT_GT(t.samples().size(), 30u) << sh.name;
        for (const auto& s : t.samples()) {
            ASSERT_TRUE(s.position.x >= 0 && s.position.x < sh.width && s.position.y >= 0 &&
                        s.position.y < sh.height)
                << sh.name;
        }
    }
}

} // namespace
} // namespace gt::foveation
