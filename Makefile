# proprio: `make demo` and `make test` are the two commands a user needs (README.md).
BUILD ?= build
BUILD_ASAN ?= build-asan
BUILD_FUZZ ?= build-fuzz
FUZZ_SECONDS ?= 60
# Every target in tests/fuzz (fuzz_<name>.cpp), so that a new parser's target is never left out.
FUZZ_TARGETS ?= $(sort $(patsubst tests/fuzz/fuzz_%.cpp,%,$(wildcard tests/fuzz/fuzz_*.cpp)))
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: deps configure build demo test test-unit test-asan fuzz bench install format lint clean

deps:
	bash scripts/install-deps

configure: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# out/demo/: every step's results; last, the learn run and its page out/demo/report.html.
demo: build
	bash scripts/demo $(BUILD)/app/proprio

test-unit: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer (no -Werror with them).
test-asan: deps
	cmake -S . -B $(BUILD_ASAN) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPROPRIO_SANITIZE=ON \
	  -DPROPRIO_BUILD_BENCH=OFF $(CMAKE_FLAGS)
	cmake --build $(BUILD_ASAN) -j $(JOBS)
	cd $(BUILD_ASAN) && ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS) -LE 'slow|golden'

test: test-unit lint test-asan

# libFuzzer on every parser of outside input (tests/fuzz), FUZZ_SECONDS each, with clang and
# ASan/UBSan, in its own build tree. New crash inputs land in $(BUILD_FUZZ)/fuzz-crashes/<target>/;
# executions are appended to $(BUILD_FUZZ)/fuzz-log.tsv (docs/results/reliability.md).
fuzz: deps
	cmake -S . -B $(BUILD_FUZZ) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DPROPRIO_FUZZ=ON -DPROPRIO_BUILD_BENCH=OFF $(CMAKE_FLAGS)
	cmake --build $(BUILD_FUZZ) -j $(JOBS) --target fuzz_targets
	bash scripts/fuzz $(BUILD_FUZZ) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

bench: build
	@for b in $(BUILD)/bench/bench_*; do [ -x $$b ] && $$b; done

install: build
	cmake --install $(BUILD)

format:
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

# clang-tidy on both cores; any warning fails. Installs nothing (run `make deps` once); configures
# the build and stamps version.hpp if needed. Clean results of unchanged files are remembered
# (scripts/lint says how).
lint:
	@test -f $(BUILD)/compile_commands.json || \
	  cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null
	cmake --build $(BUILD) --target proprio_version >/dev/null
	/usr/bin/python3 scripts/lint $(BUILD) -j $(JOBS)

clean:
	rm -rf $(BUILD) $(BUILD_ASAN) $(BUILD_FUZZ)
