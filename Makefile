# Patina's two commands (see README.md):
#   make demo   set everything up, then render the bundled car paint on the preview object under the studio map
#   make test   set everything up, then lint (ruff) and run the C++ tests (ctest; once more under
#               AddressSanitizer + UBSan, make check-sanitize) and the Python tests (pytest)
# and a few more for developers: make bench, make samples, make setup, make check-sanitize, make clean.

PY        := .venv/bin/python
PATINA    := .venv/bin/patina
STAMP     := .venv/.patina-installed
CPP_BUILD := build/cpp
SAN_BUILD := build/cpp-sanitize
SOURCES   := $(shell find core brdf fit render python -name '*.cpp' -o -name '*.h' -o -name '*.py' 2>/dev/null) \
             CMakeLists.txt pyproject.toml tools/setup.sh tools/requirements-build.txt
DEMO_OUT  := demo-out
DEMO_TABLE := materials/carpaint-base.ptab
DEMO_SCENE := materials/scenes/preview-ball.json

.PHONY: demo test lint test-cpp check-sanitize test-python bench samples setup clean

setup: $(STAMP)

$(STAMP): $(SOURCES)
	bash tools/setup.sh
	@touch $@

demo: setup
	@mkdir -p $(DEMO_OUT)
	$(PATINA) info $(DEMO_TABLE)
	$(PATINA) render $(DEMO_SCENE) --out $(DEMO_OUT)/preview.exr --force  # make demo runs again
	@echo "demo: car-paint preview in $(DEMO_OUT)/preview.png (tone-mapped) and $(DEMO_OUT)/preview.exr (float, AOVs)"

test: lint test-cpp check-sanitize test-python
test lint test-cpp check-sanitize test-python: export PATINA_SETUP_WERROR := ON

lint: setup
	.venv/bin/ruff check python tests tools
	.venv/bin/ruff format --check python tests tools

# build/cpp is the tree tools/setup.sh builds the Python module in (with the tests, -Werror when
# make test runs it), so after setup this build has nothing left to compile.
test-cpp: setup
	cmake -S . -B $(CPP_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(CURDIR)/$(PY) \
	      -DPATINA_BUILD_PYTHON=ON -DPATINA_BUILD_TESTS=ON -DPATINA_WERROR=ON
	cmake --build $(CPP_BUILD) -j 2
	ctest --test-dir $(CPP_BUILD) --output-on-failure -j 2

# The C++ tests under ASan + UBSan at -O1 (any finding aborts the test: -fno-sanitize-recover);
# headers_compile_alone and avx512_only_in_width_16 are checks of the build (a compile, a
# disassembly) that test-cpp already made on the Release build, not runs to sanitize.
check-sanitize: setup
	cmake -S . -B $(SAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
	      -DPATINA_BUILD_PYTHON=OFF -DPATINA_BUILD_TESTS=ON -DPATINA_WERROR=ON -DPATINA_SANITIZE=ON
	cmake --build $(SAN_BUILD) -j 2
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	      ctest --test-dir $(SAN_BUILD) --output-on-failure -j 2 -E '^(headers_compile_alone|avx512_only_in_width_16)$$'

test-python: setup
	$(PY) -m pytest -q tests/python

bench: setup
	$(PATINA) bench --json bench-out.json --force  # make bench runs again

# The README's sample MERL file (35 MB, so made here, not kept in git); materials/samples/red-plastic.md.
samples: setup
	$(PY) tools/make_samples.py --merl-only

clean:
	rm -rf build .venv $(DEMO_OUT) bench-out.json
