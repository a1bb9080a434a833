# Two commands on a fresh Debian machine:
#   make run   - install missing packages (as root), build, render a foveated sequence of the
#                built-in market following a gaze trace, the reference and debug views to out/
#   make test  - the same setup, then every test (lavapipe, Khronos validation on)
BUILD ?= build
PRESET ?= default
JOBS ?= $(shell nproc)
export XDG_RUNTIME_DIR ?= /tmp/gazetrace-xdg

.PHONY: all deps configure build run test clean asan format

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@mkdir -p $(XDG_RUNTIME_DIR)
	@cmake --preset $(PRESET) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The thesis's main job: a short foveated sequence on the built-in market following a recorded
# saccade, the full-resolution reference beside it, and the debug views, all in out/.
run: build
	@mkdir -p out
	./$(BUILD)/gazetrace render --method foveated --profile fove --interp msm --k 10 \
	    --rays-per-point 4 --gaze-trace content/gaze/saccade.csv --frame-ms 100 \
	    --out out/foveated --graph out/foveated_graph.dot --json
	./$(BUILD)/gazetrace render --method reference --width 1280 --height 1440 --spp 4 \
	    --out out/reference.png --json
	./$(BUILD)/gazetrace render --method foveated --view points --rays-per-point 1 --out out/view_points.png
	./$(BUILD)/gazetrace render --method foveated --view cells --rays-per-point 1 --out out/view_cells.png
	./$(BUILD)/gazetrace render --method foveated --view eccentricity --rays-per-point 1 \
	    --out out/view_eccentricity.png
	@echo "wrote out/foveated/frame_*.png, out/reference.png, out/view_*.png"

test: build
	cd $(BUILD) && ctest --output-on-failure -j 2 --timeout 900

# LeakSanitizer is off: Mesa's llvmpipe keeps allocations alive by design.
asan:
	ASAN_OPTIONS=detect_leaks=0 $(MAKE) PRESET=asan BUILD=build-asan test

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) build-asan out
