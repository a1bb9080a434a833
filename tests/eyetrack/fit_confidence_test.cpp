// The starburst detector's confidence stage: the outline's support, its sharpness, a dark inside,
// the shape ramp and size consistency, and the priors the detector learns from its answers.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pupil/fit_confidence.hpp"
#include "pupil/pupil_priors.hpp"

namespace gt::eyetrack::starburst {
namespace {

const RayLevels kLevels{.pupil = 30.0, .surround = 130.0, .threshold = 80.0, .glint = 240.0};

cv::Mat disc(double blur = 0.0) {
    cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(130));
    cv::circle(grey, {160, 120}, 25, cv::Scalar(30), cv::FILLED, cv::LINE_AA);
    if (blur > 0.0) cv::GaussianBlur(grey, grey, {0, 0}, blur);
    return grey;
}

const cv::RotatedRect kTrue({160.0F, 120.0F}, {50.0F, 50.0F}, 0.0F);

TEST(FitConfidence, AWholeCrispPupilIsFullySupported) {
    const OutlineSupport s = outlineSupport(disc(), kTrue, kLevels);
    EXPECT_GT(s.all, 0.95);
    EXPECT_GT(s.visible, 0.95);
    EXPECT_GT(s.sharpness, 0.6);
    const FitEvidence ev = judgeFit(disc(), kTrue, kLevels, 0.3, 0.8);
    EXPECT_GT(ev.confidence, 0.9);
    EXPECT_GT(ev.fill, 0.9);
    EXPECT_NEAR(ev.interior, 30.0, 2.0);
    EXPECT_NEAR(ev.outside, 130.0, 2.0);
    EXPECT_NEAR(ev.axisRatio, 1.0, 1e-6);
    EXPECT_DOUBLE_EQ(ev.shapeFactor, 1.0);
}

TEST(FitConfidence, AShadowsRampIsNotSharp) {
    // The same disc blurred over many pixels: still darker inside, but no crisp edge.
    const OutlineSupport s = outlineSupport(disc(6.0), kTrue, kLevels);
    EXPECT_LT(s.sharpness, 0.5);
    EXPECT_LT(judgeFit(disc(6.0), kTrue, kLevels, 0.3, 0.8).quality,
              judgeFit(disc(), kTrue, kLevels, 0.3, 0.8).quality);
}

TEST(FitConfidence, ALidLowersAllButNotVisible) {
    cv::Mat grey = disc();
    cv::rectangle(grey, {0, 0}, {319, 119}, cv::Scalar(180), cv::FILLED); // covers the top half
    const OutlineSupport s = outlineSupport(grey, kTrue, kLevels);
    EXPECT_LT(s.all, 0.6);
    EXPECT_GT(s.visible, 0.9);
}

TEST(FitConfidence, AWrongEllipseIsNotSupported) {
    const cv::RotatedRect off({220.0F, 60.0F}, {50.0F, 50.0F}, 0.0F);
    EXPECT_LT(outlineSupport(disc(), off, kLevels).all, 0.1);
    EXPECT_LT(judgeFit(disc(), off, kLevels, 0.3, 0.8).confidence, 0.1);
}

TEST(FitConfidence, FlatShapesLoseConfidence) {
    const cv::RotatedRect flat({160.0F, 120.0F}, {50.0F, 12.0F}, 0.0F); // ratio 0.24
    EXPECT_DOUBLE_EQ(judgeFit(disc(), flat, kLevels, 0.3, 0.8).shapeFactor, 0.0);
    // The round end follows the eye: never rounder than configured, nor within 0.1 of flat.
    EXPECT_DOUBLE_EQ(roundAxisRatio(0.8, 0.3, 0.1, 0.0), 0.8);
    EXPECT_DOUBLE_EQ(roundAxisRatio(0.8, 0.3, 0.1, 0.6), 0.5);
    EXPECT_DOUBLE_EQ(roundAxisRatio(0.8, 0.3, 0.1, 1.0), 0.8);
    EXPECT_DOUBLE_EQ(roundAxisRatio(0.8, 0.3, 0.1, 0.3), 0.4);
    EXPECT_DOUBLE_EQ(roundAxisRatio(0.8, 0.3, 0.0, 0.6), 0.8);
}

TEST(FitConfidence, SizeConsistency) {
    EXPECT_DOUBLE_EQ(sizeConsistency(40.0, 0.0), 1.0); // nothing known
    EXPECT_DOUBLE_EQ(sizeConsistency(20.0, 20.0), 1.0);
    EXPECT_NEAR(sizeConsistency(28.0, 20.0), 0.6, 0.05);
    EXPECT_NEAR(sizeConsistency(20.0, 28.0), sizeConsistency(28.0, 20.0), 1e-12);
    EXPECT_LT(sizeConsistency(60.0, 20.0), 0.01);
}

TEST(FitConfidence, MedianBeyondSeesWhatALargerFitAdds) {
    cv::Mat grey = disc();
    cv::rectangle(grey, {0, 0}, {319, 100}, cv::Scalar(200), cv::FILLED);
    // A wider ellipse reaching up under the lid adds lid skin; a smaller one adds nothing.
    const cv::RotatedRect small({160.0F, 125.0F}, {50.0F, 40.0F}, 0.0F);
    const cv::RotatedRect larger({160.0F, 112.0F}, {50.0F, 70.0F}, 0.0F);
    EXPECT_GT(medianBeyond(grey, larger, small, kLevels.glint), 150.0);
    EXPECT_DOUBLE_EQ(medianBeyond(grey, small, small, kLevels.glint), -1.0);
}

PickedAnswer answer(double semiMajor, double confidence) {
    PickedAnswer a;
    a.result.ellipse = cv::RotatedRect(
        {100.0F, 100.0F}, {static_cast<float>(2 * semiMajor), static_cast<float>(2 * semiMajor)},
        0.0F);
    a.result.confidence = confidence;
    a.supportAll = 1.0;
    a.interior = 30.0;
    a.outside = 120.0;
    a.uniform = true;
    return a;
}

TEST(PupilPriors, LearnOnlyFromConfidentUniformAnswers) {
    PupilPriors priors;
    priors.learn(answer(20.0, 0.5), 0.1);
    EXPECT_EQ(priors.recentRadius, 0.0);
    priors.learn(answer(20.0, 0.9), 0.1);
    EXPECT_DOUBLE_EQ(priors.recentRadius, 20.0);
    EXPECT_DOUBLE_EQ(priors.recentLevel, 30.0);
    EXPECT_DOUBLE_EQ(priors.recentContrast, 90.0);
    EXPECT_DOUBLE_EQ(priors.eyeRatio, 1.0);
    priors.learn(answer(30.0, 0.9), 0.1);
    EXPECT_DOUBLE_EQ(priors.recentRadius, 21.0); // a tenth of the new size
    PickedAnswer iris = answer(60.0, 0.95);
    iris.uniform = false; // a darker blob inside: an iris, not the pupil
    priors.learn(iris, 0.1);
    EXPECT_DOUBLE_EQ(priors.recentRadius, 21.0);
    // Lost for long: forgotten.
    for (int i = 0; i < 301; ++i)
        priors.learn(answer(20.0, 0.1), 0.1);
    EXPECT_EQ(priors.recentRadius, 0.0);
    EXPECT_EQ(priors.recentLevel, -1.0);
    priors.learn(answer(20.0, 0.9), 0.1);
    priors.reset();
    EXPECT_EQ(priors.recentRadius, 0.0);
    EXPECT_EQ(priors.eyeRatio, 0.0);
}

} // namespace
} // namespace gt::eyetrack::starburst
