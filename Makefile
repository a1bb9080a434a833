# Two commands on a fresh Debian machine:
#   make run   - install missing packages (as root), build, render a foveated sequence of the
#                built-in market following a gaze trace, the reference and debug views to out/
#   make test  - the same setup, then every test (lavapipe, Khronos validation on)
BUILD ?= build
PRESET ?= default
JOBS ?= $(shell nproc)
export XDG_RUNTIME_DIR ?= /tmp/gazetrace-xdg

.PHONY: all deps configure build run test clean asan fuzz format

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@mkdir -p $(XDG_RUNTIME_DIR)
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The thesis's main job: a short foveated sequence on the built-in market following a recorded
# saccade, the same with eccentricity layers (Guenter et al. 2012), the full-resolution reference beside
# them, the debug views, and a path-traced foveated frame with its path-traced reference, all
# in out/.
run: build
	@mkdir -p out
	./$(BUILD)/gazetrace render --method foveated --profile fove --interp msm --k 10 \
	    --rays-per-point 4 --gaze-trace content/gaze/saccade.csv --frame-ms 100 \
	    --out out/foveated --graph out/foveated_graph.dot --json
	./$(BUILD)/gazetrace render --method layers --profile fove --slope A \
	    --gaze-trace content/gaze/saccade.csv --frame-ms 100 --out out/layers --json
	./$(BUILD)/gazetrace render --method reference --width 1280 --height 1440 --spp 4 \
	    --out out/reference.png --json
	./$(BUILD)/gazetrace render --method foveated --view points --rays-per-point 1 --out out/view_points.png
	./$(BUILD)/gazetrace render --method foveated --view cells --rays-per-point 1 --out out/view_cells.png
	./$(BUILD)/gazetrace render --method foveated --view eccentricity --rays-per-point 1 \
	    --out out/view_eccentricity.png
	./$(BUILD)/gazetrace render --method foveated --profile fove --interp msm --k 10 \
	    --rays-per-point 4 --integrator path --bounces 3 --frames 4 --out out/path_foveated --json
	./$(BUILD)/gazetrace render --method reference --width 1280 --height 1440 --spp 16 \
	    --integrator path --bounces 3 --out out/path_reference.png --json
	@echo "wrote out/foveated/frame_*.png, out/layers/frame_*.png, out/reference.png, out/view_*.png,"
	@echo "      out/path_foveated/frame_*.png and out/path_reference.png (path traced)"

test: build
	cd $(BUILD) && ctest --output-on-failure -j 2 --timeout 900

# The sanitizer build: clang, ASan + UBSan (undefined behaviour aborts), warnings as errors, and
# the fuzz targets linked against libFuzzer; every test, including the replay of each fuzz
# target's seeds and regression cases. LeakSanitizer is off: Mesa's llvmpipe keeps allocations
# alive by design.
asan:
	ASAN_OPTIONS=detect_leaks=0 $(MAKE) PRESET=asan BUILD=build-asan test

# Each fuzz target for FUZZ_SECONDS (default 60), FUZZ_JOBS at once; figures per target, and a
# non-zero exit when any found a crash, hang, leak or out-of-memory input (build-asan/fuzz-findings).
FUZZ_SECONDS ?= 60
fuzz:
	$(MAKE) PRESET=asan BUILD=build-asan build
	bash scripts/fuzz.sh build-asan $(FUZZ_SECONDS)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) build-asan out
