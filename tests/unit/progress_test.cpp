// Progress lines of long steps: none for a step that ends within the quiet time (short runs and
// the tests that compare output print nothing new), then at most one per interval.
#include <gtest/gtest.h>

#include <string>

#include "core/progress.hpp"

namespace gt {
namespace {

TEST(Progress, QuietForShortStepsThenOneLinePerInterval) {
    double now = 100.0;
    progress::Step step("building the k-NN table", 200, [&] { return now; });
    now += 1.0;
    EXPECT_FALSE(step.advance(50).has_value()); // 1 s in: still quiet
    now += 1.5;
    const auto first = step.advance(32);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(*first, "building the k-NN table 41 % (82/200, 2 s)");
    now += 1.0;
    EXPECT_FALSE(step.advance().has_value()); // within the interval of the last line
    now += 1.5;
    EXPECT_TRUE(step.advance().has_value());
    now += 2.5;
    const auto last = step.reach(1.0);
    ASSERT_TRUE(last.has_value());
    EXPECT_NE(last->find("100 % (200/200"), std::string::npos) << *last;
}

TEST(Progress, NeverPastTheTotal) {
    double now = 0.0;
    progress::Step step("frames", 3, [&] { return now; });
    now = 10.0;
    const auto line = step.advance(7);
    ASSERT_TRUE(line.has_value());
    EXPECT_NE(line->find("100 % (3/3"), std::string::npos) << *line;
}

} // namespace
} // namespace gt
