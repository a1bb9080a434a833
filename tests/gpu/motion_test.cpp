// Motion in TAA (taa.glsl, TAA_MOTION), on images built here so that every pixel's surface,
// motion and signature is known: a striped box moving over a still background, and a shadow
// moving over a still floor, seen by a still camera with the gaze still — the view where TAA's
// history counts most (its running mean over up to 64 frames, no clipping, no distance test).
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "readback/readback.hpp"
#include "render_graph/render_graph.hpp"
#include "support/gpu_test_context.hpp"
#include "support/graph_fill.hpp"
#include "taa/taa.hpp"
#include "vk/resources.hpp"

namespace gt {
namespace {

constexpr uint32_t kW = 64, kH = 32;

// The signature code the passes store (shaders/common/motion.glsl): 16 bits of the surface id
// above the 8 of the shadow mask.
float signatureCode(uint32_t surface, uint32_t shadowMask) {
    return static_cast<float>(((surface & 0xffffu) << 8u) | (shadowMask & 0xffu));
}

// What a tracer would leave for one frame: radiance (a = first-hit distance) and motion
// (xyz = world position one frame ago minus now, w = the signature code).
struct TracedFrame {
    std::vector<glm::vec4> radiance, motion;
};

// A pinhole at the origin looking down -z, tan(yfov / 2) = 0.5, aspect 2: at distance 5 a
// pixel is 0.15625 scene units wide.
shaders::trace::CameraPush camera() {
    shaders::trace::CameraPush c{};
    c.origin = glm::vec4(0.0f, 0.0f, 0.0f, 0.5f);
    c.forward = glm::vec4(0.0f, 0.0f, -1.0f, 2.0f);
    c.right = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
    c.up = glm::vec4(0.0f, 1.0f, 0.0f, 0.0f);
    return c;
}

// The ray through a pixel's centre with z = -1 (as taa.glsl builds it, unnormalised).
glm::vec3 ray(uint32_t x, uint32_t y) {
    const float sx = (static_cast<float>(x) + 0.5f) / kW * 2.0f - 1.0f;
    const float sy = (static_cast<float>(y) + 0.5f) / kH * 2.0f - 1.0f;
    return {sx * 1.0f, -sy * 0.5f, -1.0f};
}

constexpr float kPixelAt5 = 0.15625f;
constexpr glm::vec3 kBackground{0.2f, 0.2f, 0.2f};

// A box 16 px wide in the plane z = -5, its left edge at `left` scene units, moving `step`
// units along x each frame, over a grey wall at z = -10. Its colour is a sawtooth along the
// box (period 8 px), so history taken from the wrong place on the box is wrong.
TracedFrame boxFrame(float left, float step) {
    TracedFrame f{std::vector<glm::vec4>(kW * kH), std::vector<glm::vec4>(kW * kH)};
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 0; x < kW; ++x) {
            const glm::vec3 d = ray(x, y);
            const glm::vec3 onBox = 5.0f * d;
            const float u = (onBox.x - left) / kPixelAt5; // box pixels from its left edge
            const std::size_t i = y * kW + x;
            if (u >= 0.0f && u < 16.0f && std::abs(onBox.y) < 1.5f) {
                const float g = 0.1f + 0.8f * (u / 8.0f - std::floor(u / 8.0f));
                f.radiance[i] = glm::vec4(0.9f, g, 0.1f, glm::length(onBox));
                f.motion[i] = glm::vec4(-step, 0.0f, 0.0f, signatureCode(2, 1));
            } else {
                f.radiance[i] = glm::vec4(kBackground, glm::length(10.0f * d));
                f.motion[i] = glm::vec4(0.0f, 0.0f, 0.0f, signatureCode(1, 1));
            }
        }
    }
    return f;
}

bool onBox(const TracedFrame& f, std::size_t i) {
    return f.motion[i].w == signatureCode(2, 1);
}

constexpr glm::vec3 kLit{0.6f, 0.6f, 0.6f}, kShadowed{0.05f, 0.05f, 0.05f};

// A still floor (the wall at z = -10) with a shadow 12 px wide whose left edge is at pixel
// column `left`: no surface moves, only which light reaches it (the signature's shadow mask).
// The lit floor's radiance is kLit times `litScale` (a frame's noise).
TracedFrame shadowFrame(int left, float litScale = 1.0f) {
    TracedFrame f{std::vector<glm::vec4>(kW * kH), std::vector<glm::vec4>(kW * kH)};
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 0; x < kW; ++x) {
            const bool shadowed = static_cast<int>(x) >= left && static_cast<int>(x) < left + 12;
            const std::size_t i = y * kW + x;
            f.radiance[i] =
                glm::vec4(shadowed ? kShadowed : litScale * kLit, glm::length(10.0f * ray(x, y)));
            f.motion[i] = glm::vec4(0.0f, 0.0f, 0.0f, signatureCode(1, shadowed ? 0u : 1u));
        }
    }
    return f;
}

float maxDiff(glm::vec3 a, glm::vec3 b) {
    const glm::vec3 d = glm::abs(a - b);
    return std::max(d.x, std::max(d.y, d.z));
}

class MotionTaaTest : public test::GpuTest {
protected:
    // One frame through TaaPass: the still view's blend (gaze still, `samples` frames held),
    // with the frame's motion unless `withMotion` is false, with a support of 0 (each frame
    // pooled at full weight) when `withSupport`. Returns the output's rgb.
    std::vector<glm::vec3> run(const TracedFrame& f, uint32_t samples, bool withMotion,
                               bool withSupport) {
        rg::RenderGraph g(kW, kH);
        std::vector<vk::Buffer> uploads;
        auto upload = [&](const char* name, const std::vector<glm::vec4>& texels) {
            const std::span<const std::byte> bytes = std::as_bytes(std::span(texels));
            uploads.emplace_back(ctx(),
                                 vk::BufferDesc{bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                vk::MemoryUsage::Upload, name});
            uploads.back().upload(bytes);
            const std::string uploaded = std::string(name) + ".upload";
            const rg::BufferId src =
                g.importBuffer(uploaded, {uploads.back().handle(), uploads.back().size(),
                                          std::nullopt, std::nullopt});
            return test::addUploadedTexture(g, name, src, VK_FORMAT_R32G32B32A32_SFLOAT);
        };
        const rg::TextureId current = upload("current", f.radiance);
        std::optional<passes::TaaMotion> motion;
        if (withMotion) {
            motion = passes::TaaMotion{
                upload("motion", f.motion),
                g.importHistory(mHistory, "taa.signature", passes::kTaaSignatureFormat, kW, kH),
                {}};
        }
        std::optional<passes::TaaSupport> support;
        if (withSupport) {
            support = passes::TaaSupport{
                test::addFilledTexture(g, "support", {VK_FORMAT_R32_SFLOAT}, glm::vec4(0.0f)),
                g.importHistory(mHistory, "taa.weight", VK_FORMAT_R32_SFLOAT, kW, kH)};
        }
        const rg::HistoryTextures h =
            g.importHistory(mHistory, "taa", VK_FORMAT_R32G32B32A32_SFLOAT, kW, kH);
        const passes::TaaFrameState state{0.0f, glm::vec2(32.0f), true, samples > 0, samples};
        const rg::TextureId out =
            mTaa.add(g, h, current, camera(), camera(), samples == 0, {}, state, support, motion);
        const std::vector<glm::vec4> px = test::executeAndRead(ctx(), g, out, &mHistory);
        std::vector<glm::vec3> rgb(px.size());
        std::transform(px.begin(), px.end(), rgb.begin(), [](glm::vec4 p) { return glm::vec3(p); });
        return rgb;
    }

    // Frames 0..n-1 of `scene`; after each, `check(frame, output)`.
    void play(const std::function<TracedFrame(uint32_t)>& scene, uint32_t n, bool withMotion,
              bool withSupport,
              const std::function<void(uint32_t, const std::vector<glm::vec3>&)>& check) {
        for (uint32_t i = 0; i < n; ++i) {
            check(i, run(scene(i), i, withMotion, withSupport));
        }
    }

    rg::HistoryPool mHistory{ctx()};
    passes::TaaPass mTaa{ctx()};
};

constexpr float kStep = 3.0f * kPixelAt5; // the box moves 3 px a frame

// Where the box was and is: the worst error over the pixels it left this frame (they must show
// the wall at once: no trail), and over its inside (history taken where each point was, so the
// sawtooth stays sharp).
struct BoxErrors {
    float trail = 0.0f, inside = 0.0f;
};

bool insideBox(const TracedFrame& f, uint32_t x, uint32_t y) {
    for (uint32_t dy = 0; dy < 3; ++dy) {
        for (uint32_t dx = 0; dx < 3; ++dx) {
            if (!onBox(f, (y + dy - 1) * kW + x + dx - 1)) return false;
        }
    }
    return true;
}

BoxErrors boxErrors(const TracedFrame& before, const TracedFrame& now,
                    const std::vector<glm::vec3>& out) {
    BoxErrors e;
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 1; x + 1 < kW; ++x) {
            const std::size_t i = y * kW + x;
            if (onBox(before, i) && !onBox(now, i)) {
                e.trail = std::max(e.trail, maxDiff(out[i], kBackground));
            }
            // Inside: no edge in its 3x3 neighbourhood, whose spread clips the history.
            if (y > 0 && y + 1 < kH && insideBox(now, x, y)) {
                e.inside = std::max(e.inside, maxDiff(out[i], glm::vec3(now.radiance[i])));
            }
        }
    }
    return e;
}

class MotionTaaBoxTest : public MotionTaaTest, public ::testing::WithParamInterface<bool> {};

TEST_P(MotionTaaBoxTest, AMovingBoxLeavesNoTrail) {
    const bool support = GetParam();
    auto scene = [](uint32_t i) { return boxFrame(-3.0f + kStep * static_cast<float>(i), kStep); };
    play(scene, 10, true, support, [&](uint32_t i, const std::vector<glm::vec3>& out) {
        if (i == 0) return;
        const BoxErrors e = boxErrors(scene(i - 1), scene(i), out);
        EXPECT_LT(e.trail, 0.01f) << "frame " << i << ": the box's colour stays where it left";
        EXPECT_LT(e.inside, 0.01f) << "frame " << i << ": the box's history from elsewhere";
    });
}

INSTANTIATE_TEST_SUITE_P(PooledOrNot, MotionTaaBoxTest, ::testing::Bool());

// What the motion is for: without it the still view's running mean keeps the box's colour
// wherever it went (a trail fading over the 64 frames of the mean).
TEST_F(MotionTaaTest, WithoutMotionTheBoxLeavesATrail) {
    auto scene = [](uint32_t i) { return boxFrame(-3.0f + kStep * static_cast<float>(i), kStep); };
    float worst = 0.0f;
    play(scene, 6, false, false, [&](uint32_t i, const std::vector<glm::vec3>& out) {
        if (i > 0) worst = std::max(worst, boxErrors(scene(i - 1), scene(i), out).trail);
    });
    EXPECT_GT(worst, 0.1f);
}

// A shadow moving over a still floor: nothing moves but which light reaches the floor (its
// signature's shadow mask), so the floor it left must be lit at once.
TEST_F(MotionTaaTest, AMovingShadowLeavesNoTrail) {
    auto scene = [](uint32_t i) { return shadowFrame(4 + 3 * static_cast<int>(i)); };
    play(scene, 10, true, true, [&](uint32_t i, const std::vector<glm::vec3>& out) {
        if (i == 0) return;
        float trail = 0.0f, lit = 0.0f;
        const TracedFrame before = scene(i - 1), now = scene(i);
        for (std::size_t p = 0; p < out.size(); ++p) {
            const bool wasShadowed = before.motion[p].w == signatureCode(1, 0);
            const bool isShadowed = now.motion[p].w == signatureCode(1, 0);
            if (wasShadowed && !isShadowed) trail = std::max(trail, maxDiff(out[p], kLit));
            if (!wasShadowed && !isShadowed) lit = std::max(lit, maxDiff(out[p], kLit));
        }
        EXPECT_LT(trail, 0.01f) << "frame " << i << ": the shadow stays where it left";
        EXPECT_LT(lit, 1e-5f) << "frame " << i << ": the still, lit floor changed";
    });
}

// A history stands for no more frames than it gathered: floor uncovered by a shadow at frame 4
// is, 6 frames later, the mean of those 6 noisy frames (kLit, the noise alternating +-20 %),
// as the floor never shadowed is the mean of all 10, not mostly the frame it was uncovered in.
TEST_F(MotionTaaTest, UncoveredFloorIsTheMeanOfTheFramesSinceItWasUncovered) {
    auto scene = [](uint32_t i) { return shadowFrame(i < 4 ? 20 : 40, i % 2 == 0 ? 1.2f : 0.8f); };
    std::vector<glm::vec3> last;
    play(scene, 10, true, false, [&](uint32_t, const std::vector<glm::vec3>& out) { last = out; });
    float uncovered = 0.0f, open = 0.0f;
    for (uint32_t y = 0; y < kH; ++y) {
        for (uint32_t x = 0; x < 16; ++x)
            open = std::max(open, maxDiff(last[y * kW + x], kLit));
        // Columns 20-31 were uncovered at frame 4; their edges' neighbourhoods changed too.
        for (uint32_t x = 22; x < 30; ++x) {
            uncovered = std::max(uncovered, maxDiff(last[y * kW + x], kLit));
        }
    }
    EXPECT_LT(open, 1e-4f) << "the floor never shadowed";
    EXPECT_LT(uncovered, 1e-4f) << "the floor uncovered 6 frames ago";
}

// A still edge: jittered samples make column 31's nearest sample alternate between a still box
// (bright) and the wall behind it every frame. Nothing moves, so its history is its past (the
// edge's coverage), and it converges to the mean of the two, as in a still scene, instead of
// being rejected every frame and showing whichever side this frame's sample fell on.
TEST_F(MotionTaaTest, AStillEdgeWhoseSamplesAlternateKeepsItsHistory) {
    constexpr glm::vec3 kBox{0.9f, 0.9f, 0.9f};
    auto scene = [&](uint32_t i) {
        TracedFrame f{std::vector<glm::vec4>(kW * kH), std::vector<glm::vec4>(kW * kH)};
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x < kW; ++x) {
                const bool box = x < 31 || (x == 31 && i % 2 == 0);
                const float depth = box ? 5.0f : 10.0f;
                const std::size_t p = y * kW + x;
                f.radiance[p] = glm::vec4(box ? kBox : kBackground, glm::length(depth * ray(x, y)));
                f.motion[p] = glm::vec4(0.0f, 0.0f, 0.0f, signatureCode(box ? 2 : 1, 1));
            }
        }
        return f;
    };
    std::vector<glm::vec3> last;
    play(scene, 10, true, false, [&](uint32_t, const std::vector<glm::vec3>& out) { last = out; });
    float edge = 0.0f;
    for (uint32_t y = 0; y < kH; ++y) {
        edge = std::max(edge, maxDiff(last[y * kW + 31], 0.5f * (kBox + kBackground)));
    }
    EXPECT_LT(edge, 1e-4f) << "the still edge's pixel is not the mean of its frames";
}

// A moving edge: a plain box slides 2 px a frame over the wall, and jittered samples make the
// column at its leading edge show the box on even frames and the wall on odd ones (the column
// behind its trailing edge the other way round). The column follows the box (the nearest moving
// surface beside it), so its history is the edge's own past and holds its coverage: after 8
// frames it is the mean of the two, where rejecting the other surface's history would show
// whichever side this frame's sample fell on (0.35 off on the last, odd frame). The moved
// pixel's variance clipping pulls the history a little towards this frame's neighbourhood
// (measured: 0.017 off). Nothing the box left keeps its colour: not the mix a trailing-edge
// pixel held while it followed the box (kEdgeMixBit: it is clipped once off the edge), nor a
// Catmull-Rom history ringing below the wall's colour beside the edge.
TEST_F(MotionTaaTest, AMovingEdgeWhoseSamplesAlternateKeepsItsCoverage) {
    constexpr glm::vec3 kBox{0.9f, 0.9f, 0.9f};
    constexpr float kTwoPixels = 2.0f * kPixelAt5;
    auto left = [](uint32_t i) { return 4u + 2u * i; };
    auto right = [](uint32_t i) { return 20u + 2u * i; }; // the leading edge's column
    auto scene = [&](uint32_t i) {
        TracedFrame f{std::vector<glm::vec4>(kW * kH), std::vector<glm::vec4>(kW * kH)};
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x < kW; ++x) {
                const bool box = (x >= left(i) && x < right(i)) || (x == right(i) && i % 2 == 0) ||
                                 (x + 1 == left(i) && i % 2 == 1);
                const float depth = box ? 5.0f : 10.0f;
                const std::size_t p = y * kW + x;
                f.radiance[p] = glm::vec4(box ? kBox : kBackground, glm::length(depth * ray(x, y)));
                f.motion[p] = box ? glm::vec4(-kTwoPixels, 0.0f, 0.0f, signatureCode(2, 1))
                                  : glm::vec4(0.0f, 0.0f, 0.0f, signatureCode(1, 1));
            }
        }
        return f;
    };
    std::vector<glm::vec3> last;
    float trail = 0.0f;
    play(scene, 8, true, false, [&](uint32_t i, const std::vector<glm::vec3>& out) {
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x + 1 < left(i); ++x) // what the box left, and never covered
                trail = std::max(trail, maxDiff(out[y * kW + x], kBackground));
        }
        last = out;
    });
    EXPECT_LT(trail, 0.01f) << "the box's colour stays where it left";
    float edge = 0.0f;
    for (uint32_t y = 0; y < kH; ++y) {
        edge = std::max(edge, maxDiff(last[y * kW + right(7)], 0.5f * (kBox + kBackground)));
    }
    EXPECT_LT(edge, 0.05f) << "the moving edge's pixel is not the mean of its frames";
}

// The history of a surface moving by a fraction of a pixel each frame (1.5 px) is sampled
// between texels, sharpened by Catmull-Rom, whose negative lobes would overshoot at the box's
// edges (to 0.92 and 0.19 here); kept within the nearest taps' range, every pixel stays within
// the wall's and the box's colours.
TEST_F(MotionTaaTest, AHistorySampledBetweenTexelsDoesNotRingAtEdges) {
    constexpr glm::vec3 kBox{0.9f, 0.9f, 0.9f};
    constexpr float kStepPx = 1.5f;
    auto scene = [&](uint32_t i) {
        const float left = 4.0f + kStepPx * static_cast<float>(i), right = left + 16.0f;
        TracedFrame f{std::vector<glm::vec4>(kW * kH), std::vector<glm::vec4>(kW * kH)};
        for (uint32_t y = 0; y < kH; ++y) {
            for (uint32_t x = 0; x < kW; ++x) {
                const float centre = static_cast<float>(x) + 0.5f;
                // The columns holding an edge alternate between the box and the wall.
                bool box = centre >= left && centre < right;
                if (std::floor(right) == static_cast<float>(x)) box = i % 2 == 0;
                if (std::floor(left) == static_cast<float>(x)) box = i % 2 == 1;
                const float depth = box ? 5.0f : 10.0f;
                const std::size_t p = y * kW + x;
                f.radiance[p] = glm::vec4(box ? kBox : kBackground, glm::length(depth * ray(x, y)));
                f.motion[p] = box ? glm::vec4(-kStepPx * kPixelAt5, 0.0f, 0.0f, signatureCode(2, 1))
                                  : glm::vec4(0.0f, 0.0f, 0.0f, signatureCode(1, 1));
            }
        }
        return f;
    };
    float outside = 0.0f;
    play(scene, 10, true, false, [&](uint32_t, const std::vector<glm::vec3>& out) {
        for (const glm::vec3& c : out) {
            outside = std::max({outside, kBackground.x - c.x, c.x - kBox.x});
        }
    });
    EXPECT_LT(outside, 0.002f) << "the history overshoots the colours on either side of an edge";
}

} // namespace
} // namespace gt
