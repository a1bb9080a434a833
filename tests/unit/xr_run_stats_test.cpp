// `xr --json` in the units of every command (docs/json.md): rays per frame as `render` reports
// them, the run's sum as rays_total, and no gaze latency where none was measured.
#include <gtest/gtest.h>

#include "xr_run_stats.hpp"

namespace gt::app {
namespace {

render::FrameResult frame(uint64_t leftRays, uint64_t rightRays) {
    render::FrameResult f;
    f.views = {{leftRays}, {rightRays}};
    return f;
}

TEST(XrRunStats, RaysArePerFrameWithTheTotalBeside) {
    RunStats stats;
    for (int i = 0; i < 10; ++i)
        stats.addFrame(frame(1000, 1200), 5.0);
    const nlohmann::json j = stats.json();
    EXPECT_EQ(j.at("rays"), 2200u);        // both eyes, one frame
    EXPECT_EQ(j.at("rays_total"), 22000u); // the run
}

TEST(XrRunStats, GazeLatencyIsNullWhenNotMeasured) {
    RunStats ahead; // a source with no clock of its own: no gaze age
    ahead.addFrame(frame(10, 10), 5.0);
    EXPECT_TRUE(ahead.json().at("gaze_to_display_ms_median").is_null());
    RunStats tracked;
    tracked.addFrame(frame(10, 10), 5.0);
    tracked.addGazeAge(12.5);
    EXPECT_EQ(tracked.json().at("gaze_to_display_ms_median"), 12.5);
}

} // namespace
} // namespace gt::app
