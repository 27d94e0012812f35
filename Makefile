# Thin wrapper over CMake. Every target first installs the Debian packages that are missing.
JOBS ?= $(shell nproc)
RELEASE := build/release
TEST := build/test
FUZZ_SECONDS ?= 60
TSAN := build/tsan
CHECK := build/check

.PHONY: setup release run test format-check bench fuzz format clean

setup:
	@bash scripts/setup.sh

release: setup
	cmake -S . -B $(RELEASE) -DCMAKE_BUILD_TYPE=Release -DSNERT_BUILD_TESTS=OFF
	cmake --build $(RELEASE) -j $(JOBS)

run: release
	bash scripts/run.sh $(RELEASE)/snert

# The sanitizer builds' flags: -O1 (the level the sanitizers' documentation suggests) and line
# tables only (-g1: the reports still name file and line), which compile in about half the time of
# RelWithDebInfo's -O2 -g (measured on the heaviest files: 30 -> 17 s for the DICOM reader).
SANITIZER_FLAGS := -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"

# What `make test` checks, in order: formatting (format-check); the whole build under
# AddressSanitizer and UBSan with warnings as errors, and every test; the worker under
# ThreadSanitizer; a build without the GUI of the command line and the `data` tests, which run
# there (optimized).
test: format-check
	cmake -S . -B $(TEST) $(SANITIZER_FLAGS) -DSNERT_SANITIZE=address,undefined \
		-DSNERT_WERROR=ON
	cmake --build $(TEST) -j $(JOBS)
	cd $(TEST) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
		ctest --output-on-failure -j $(JOBS)
	@# The app's background worker under ThreadSanitizer: its test binary only (no GL).
	cmake -S . -B $(TSAN) $(SANITIZER_FLAGS) -DSNERT_SANITIZE=thread \
		-DSNERT_BUILD_BENCH=OFF
	cmake --build $(TSAN) --target snert_app_worker_tests -j $(JOBS)
	TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" $(TSAN)/tests/app/snert_app_worker_tests
	@# Without the GUI (no renderer, no app): the command line builds. The real-volume tests
	@# (label `data`) run again there, optimized: the two large volumes, skipped under the
	@# sanitizers, take a minute instead of ten. Only what they run is built (the libraries and
	@# unit tests compiled above, from the same sources).
	cmake -S . -B $(CHECK) -DCMAKE_BUILD_TYPE=Release -DSNERT_BUILD_GUI=OFF -DSNERT_BUILD_BENCH=OFF
	cmake --build $(CHECK) -j $(JOBS) --target snert snert_data_tests
	cd $(CHECK) && ctest -L data --output-on-failure -j $(JOBS)

# snert against VTK's flying edges (one thread) on the sphere and a 512 x 512 x 400 CT, as one
# table with the speed targets (bench/report.py). The bench-only packages (python3-vtk9,
# python3-numpy) are installed here only, not by `make test`. QUICK=1: fewer runs, one CT iso
# for `snert compare`.
bench: release
	@bash scripts/setup.sh --bench
	QUICK=$(QUICK) /usr/bin/python3 bench/report.py $(RELEASE)

# libFuzzer on snert's own header handling and raw reader (clang, outside the CMake build).
fuzz: setup
	bash tests/fuzz/run.sh $(FUZZ_SECONDS)

# Formatting of every tracked C++ file against .clang-format: reports, changes nothing
# (`make format` rewrites them).
format-check: setup
	@command -v clang-format >/dev/null || { echo "clang-format not found (Debian: clang-format)"; exit 1; }
	clang-format --dry-run --Werror $$(git ls-files '*.cpp' '*.h')

format:
	clang-format -i $$(git ls-files '*.cpp' '*.h')

clean:
	rm -rf build
