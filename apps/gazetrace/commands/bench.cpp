// `gazetrace bench`: the benchmark suites: its options and what it prints.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bench_command.hpp"
#include "command.hpp"
#include "core/error.hpp"
#include "eye_commands.hpp"
#include "option_parsing.hpp"
#include "scale_bench.hpp"
#include "shared_options.hpp"

namespace gt::app {

namespace {

class BenchCommand final : public Command {
public:
    void registerOptions(CLI::App& app) override {
        mCommand = app.add_subcommand(
            "bench", "Table 1, Table 2 and foveated vs reference on the market (Google Benchmark)");
        mCommand->add_option("--json", mOptions.json,
                             "Also write the results as JSON to this file");
        mCommand->add_flag("--quick", mOptions.quick, "Smoke test: fewer frames, no 32-ray frames");
        mCommand->add_option("--scene", mOptions.scene, "Scene for the headline comparison")
            ->capture_default_str();
        mCommand->add_option("--cache", mOptions.cacheDir, "Point-set cache folder");
        mCommand
            ->add_option("--suite", mSuite,
                         "render (thesis tables, headline, layers) | eye (pupil detection speed) | "
                         "stereo | layers (Guenter et al. 2012 only) | scale (every headset) | "
                         "animation (CPU cost of a built moving scene per frame)")
            ->check(CLI::IsMember({"render", "eye", "stereo", "layers", "scale", "animation"}))
            ->capture_default_str();
        mCommand
            ->add_option("--hmd", mOptions.hmd, "--suite stereo: the headset, " + hmdChoicesText())
            ->capture_default_str();
        addIntegratorOptions(mCommand, mOptions.integrator,
                             "--suite stereo and scale: the headset frames' reference and point "
                             "sets");
        registerScaleOptions();
    }

    int run() override {
        if (mSuite == "scale") {
            return runScale();
        }
        for (const CLI::Option* o : mScaleOnly) {
            if (o->count() > 0) {
                throw ArgumentError(o->get_name() + ": only with --suite scale");
            }
        }
        checkRunFiles({{"--json", mOptions.json}}, {{"--scene", mOptions.scene}});
        if (mSuite != "stereo" && mSuite != "scale") {
            for (const char* name : {"--integrator", "--bounces", "--sequence"}) {
                if (mCommand->count(name) > 0) {
                    throw ArgumentError(std::string(name) + ": only --suite stereo and scale");
                }
            }
        }
        if (mSuite != "stereo" && mCommand->count("--hmd") > 0) {
            throw ArgumentError("--hmd: only --suite stereo measures a headset");
        }
        if (mSuite == "animation" && mCommand->count("--scene") > 0) {
            throw ArgumentError("--scene: --suite animation measures its own built scene");
        }
        if (mSuite == "eye") {
            (void)runEyeBench();
        } else if (mSuite == "animation") {
            (void)runAnimationBench(mOptions);
        } else if (mSuite == "layers") {
            (void)runLayersBench(mOptions);
        } else if (mSuite == "stereo") {
            (void)runStereoBench(mOptions);
        } else {
            (void)runBench(mOptions);
        }
        return 0;
    }

private:
    void registerScaleOptions() {
        mScaleOnly = {
            mCommand
                ->add_option("--profiles", mScale.profiles,
                             "scale: these headsets only (--hmd names, comma-separated); default "
                             "every one")
                ->delimiter(','),
            mCommand
                ->add_option("--frames", mScale.frames,
                             "scale: timed frames per case after the warm-up (--quick: 1)")
                ->check(CLI::Range(1u, 1000u)),
            mCommand->add_option("--plot", mScale.plot,
                                 "scale: the PNG of time and ray ratios against pixels per eye "
                                 "(default: beside --json, extension .png)"),
            mCommand->add_flag("--generate-sets", mScale.generateSets,
                               "scale: generate every point set, timed, instead of loading it "
                               "from the cache"),
            // For tests: every eye at this size, its field of view kept.
            mCommand->add_option("--eye-size", mEyeSize)->group(""),
            mCommand->add_option("--eye-distance", mEyeDistance)
                ->check(CLI::Range(0.01, 1000.0))
                ->group("")};
    }

    int runScale() {
        mScale.common = mOptions;
        if (mOptions.quick && mScaleOnly[1]->count() == 0) {
            mScale.frames = 1;
        }
        if (!mEyeSize.empty()) {
            mScale.eyeSize = parseSizeText(mEyeSize);
            if (!mScale.eyeSize || mScale.eyeSize->first < 16 || mScale.eyeSize->second < 16 ||
                mScale.eyeSize->first > 8192 || mScale.eyeSize->second > 8192) {
                throw ArgumentError("--eye-size: WxH, 16 to 8192 each");
            }
        }
        if (mScaleOnly[5]->count() > 0) {
            mScale.eyeDistance = mEyeDistance;
        }
        checkRunFiles({{"--json", mOptions.json}, {"--plot", scalePlotPath(mScale)}},
                      {{"--scene", mOptions.scene}});
        (void)runScaleBench(mScale);
        return 0;
    }

    BenchOptions mOptions;
    std::string mSuite = "render";
    ScaleBenchOptions mScale;
    std::string mEyeSize;
    double mEyeDistance = 1.0;
    std::vector<CLI::Option*> mScaleOnly;
};

} // namespace

std::unique_ptr<Command> makeBenchCommand() {
    return std::make_unique<BenchCommand>();
}

} // namespace gt::app
