// The demo starts with the settings its device can afford: a GPU the quality `eval` scores best
// (its defaults), a CPU driver the fast trade-off; options given on the command line win.
#include <gtest/gtest.h>

#include "demo_settings.hpp"

namespace gt::app {
namespace {

TEST(DemoDefaults, GpusTakeEvalsBestSettings) {
    for (const VkPhysicalDeviceType t :
         {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
          VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU}) {
        const DemoDefaults d = demoDefaults(t);
        EXPECT_EQ(d.scale, 1.0) << t;
        EXPECT_EQ(d.interp, "msm") << t;
        EXPECT_EQ(d.k, 10u) << t;
        EXPECT_EQ(d.raysPerPoint, 4u) << t;
        EXPECT_EQ(d.label, "GPU quality") << t;
    }
}

TEST(DemoDefaults, CpuDriverTakesTheFastTradeOff) {
    const DemoDefaults d = demoDefaults(VK_PHYSICAL_DEVICE_TYPE_CPU);
    EXPECT_EQ(d.scale, 2.0);
    EXPECT_EQ(d.interp, "nn");
    EXPECT_EQ(d.raysPerPoint, 1u);
    EXPECT_EQ(d.label, "CPU fast");
}

TEST(DemoDefaults, GivenOptionsWin) {
    DemoSettings s;
    s.interp = "rbf";
    s.k = 7;
    s.scale = 3.0;
    s.raysPerPoint = 2;
    DemoSettings all = s;
    applyDemoDefaults(all, demoDefaults(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU),
                      {.interp = true, .k = true, .scale = true, .raysPerPoint = true});
    EXPECT_EQ(all.interp, "rbf");
    EXPECT_EQ(all.k, 7u);
    EXPECT_EQ(all.scale, 3.0);
    EXPECT_EQ(all.raysPerPoint, 2u);
    DemoSettings some = s;
    applyDemoDefaults(some, demoDefaults(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU), {.scale = true});
    EXPECT_EQ(some.interp, "msm");
    EXPECT_EQ(some.k, 10u);
    EXPECT_EQ(some.scale, 3.0);
    EXPECT_EQ(some.raysPerPoint, 4u);
    // Another method's rays are its --spp: left alone.
    DemoSettings layers = s;
    layers.method = "layers";
    applyDemoDefaults(layers, demoDefaults(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU), {});
    EXPECT_EQ(layers.raysPerPoint, 2u);
}

} // namespace
} // namespace gt::app
