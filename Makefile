# Two commands on a fresh Debian machine:
#   make run   - install missing packages (as root), build, render the built-in market to out/
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

run: build
	@mkdir -p out
	./$(BUILD)/gazetrace render --scene builtin:market --width 1280 --height 720 --spp 4 \
	    --out out/market.png --graph out/market_graph.dot --json
	@echo "wrote out/market.png (and out/market_graph.dot)"

test: build
	cd $(BUILD) && ctest --output-on-failure -j 2 --timeout 900

# LeakSanitizer is off: Mesa's llvmpipe keeps allocations alive by design.
asan:
	ASAN_OPTIONS=detect_leaks=0 $(MAKE) PRESET=asan BUILD=build-asan test

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) build-asan out
