// The starburst detector's first stage: the coarse centre-surround search must put a seed in a
// dark blob, in a pupil inside a dark iris, and its vectorised row must give the plain values.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pupil/candidate_search.hpp"

namespace gt::eyetrack::starburst {
namespace {

cv::Mat integralOf(const cv::Mat& grey) {
    cv::Mat ii;
    cv::integral(grey, ii, CV_32S);
    return ii;
}

TEST(CentreSurroundRow, FillMatchesAtEverywhere) {
    cv::Mat grey(60, 80, CV_8UC1);
    cv::RNG rng(5);
    rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
    const cv::Mat ii = integralOf(grey);
    for (const auto& [hi, ho] : {std::pair{1, 3}, std::pair{2, 4}, std::pair{5, 12}}) {
        for (const int step : {1, 2, 3}) {
            for (const int y : {0, 3, 30, 59}) {
                const CentreSurroundRow row(ii, y, hi, ho);
                const int count = (grey.cols + step - 1) / step;
                std::vector<double> out(static_cast<std::size_t>(count));
                row.fill(step, count, out.data());
                for (int k = 0; k < count; ++k) {
                    ASSERT_EQ(out[static_cast<std::size_t>(k)], row.at(k * step))
                        << "hi " << hi << " ho " << ho << " step " << step << " y " << y << " k "
                        << k;
                }
            }
        }
    }
}

TEST(CentreSurroundRow, DarkCentreRespondsPositive) {
    cv::Mat grey(40, 40, CV_8UC1, cv::Scalar(150));
    cv::circle(grey, {20, 20}, 4, cv::Scalar(30), cv::FILLED);
    const cv::Mat ii = integralOf(grey); // the row reads it: it must outlive the row
    const CentreSurroundRow row(ii, 20, 3, 7);
    EXPECT_GT(row.at(20), 60.0);
    EXPECT_LT(std::abs(row.at(5)), 1e-9); // flat: ring and centre alike
}

TEST(CandidateSearch, FindsTheDarkDiscFirst) {
    cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(140));
    cv::circle(grey, {210, 130}, 18, cv::Scalar(25), cv::FILLED);
    cv::circle(grey, {60, 60}, 9, cv::Scalar(100), cv::FILLED); // a fainter, smaller blob
    CandidateSearch search(12.0);
    std::vector<Candidate> found;
    search.find(grey, integralOf(grey), 7.2, 60.0, found, 5);
    ASSERT_FALSE(found.empty());
    EXPECT_LT(cv::norm(found.front().centre - cv::Point2d(210, 130)), 6.0);
    EXPECT_GT(found.front().radius, 8.0);
    EXPECT_LT(found.front().radius, 30.0);
    // Each candidate a different blob or scale: no two at one place and a similar scale.
    for (std::size_t i = 0; i < found.size(); ++i) {
        for (std::size_t j = i + 1; j < found.size(); ++j) {
            const double ratio = std::max(found[i].radius, found[j].radius) /
                                 std::min(found[i].radius, found[j].radius);
            EXPECT_FALSE(cv::norm(found[i].centre - found[j].centre) <
                             std::max(found[i].radius, found[j].radius) &&
                         ratio < 1.8);
        }
    }
    // The limit holds, counting what `found` held before.
    std::vector<Candidate> one{found.front()};
    search.find(grey, integralOf(grey), 7.2, 60.0, one, 2);
    EXPECT_LE(one.size(), 2U);
}

TEST(CandidateSearch, FindsAPupilInsideADarkIris) {
    cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(200));
    cv::circle(grey, {160, 120}, 50, cv::Scalar(60), cv::FILLED); // a dark iris
    cv::circle(grey, {170, 125}, 14, cv::Scalar(20), cv::FILLED); // its pupil, off-centre
    CandidateSearch search(12.0);
    std::vector<Candidate> found;
    search.find(grey, integralOf(grey), 7.2, 60.0, found, 5);
    const auto inner = search.inside({160, 120}, 50.0, 60.0, 7.2);
    ASSERT_TRUE(inner.has_value());
    EXPECT_LT(cv::norm(inner->centre - cv::Point2d(170, 125)), 6.0);
    EXPECT_LT(inner->radius, 0.7 * 50.0 + 1e-9);
}

TEST(CandidateSearch, ClosingJoinsAPupilCrossedByLashes) {
    cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(140));
    cv::circle(grey, {160, 120}, 20, cv::Scalar(30), cv::FILLED);
    for (int x = 100; x <= 220; x += 6) { // dark lashes, 2 px wide, across the pupil
        cv::line(grey, {x, 60}, {x + 10, 130}, cv::Scalar(30), 2);
    }
    CandidateSearch search(12.0);
    std::vector<Candidate> found;
    search.findClosed(grey, 13, 7.2, 60.0, found, 3);
    ASSERT_FALSE(found.empty());
    EXPECT_LT(cv::norm(found.front().centre - cv::Point2d(160, 120)), 8.0);
}

} // namespace
} // namespace gt::eyetrack::starburst
