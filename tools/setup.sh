#!/usr/bin/env bash
# Sets up everything `make demo` and `make test` need, idempotently:
#   - from Debian, only what pip cannot give: a C++ compiler, CMake, Ninja, GoogleTest,
#     EGL with Mesa's software rasteriser (off-screen OpenGL for the 3-D lobe view) and
#     Chromium (headless, to check the HTML report as a browser shows it);
#   - a virtual environment in .venv with the pinned Python packages;
#   - Patina itself (the C++ core and the Python package) built into that venv.
set -euo pipefail
cd "$(dirname "$0")/.."

need_apt=()
command -v g++ >/dev/null || need_apt+=(g++)
command -v cmake >/dev/null || need_apt+=(cmake)
command -v ninja >/dev/null || need_apt+=(ninja-build)
[ -f /usr/include/gtest/gtest.h ] || need_apt+=(libgtest-dev)
python3 -c 'import venv, ensurepip' 2>/dev/null || need_apt+=(python3-venv)
# VTK's wheel loads these at run time to render without a display (no GPU needed).
compgen -G '/usr/lib/*/libEGL_mesa.so.0' >/dev/null && compgen -G '/usr/lib/*/dri/swrast_dri.so' >/dev/null \
  || need_apt+=(libegl1 libgl1-mesa-dri)
# Mitsuba's llvm_ad_rgb variant (the render.vs_mitsuba_llvm benchmark) needs a newer libLLVM than Debian 12's default 15.
compgen -G '/usr/lib/*/libLLVM-19.so*' >/dev/null || need_apt+=(libllvm19)
# The report test (tests/python/plot) opens index.html in a real headless browser and screenshots it.
command -v chromium >/dev/null || need_apt+=(chromium)
if [ ${#need_apt[@]} -gt 0 ]; then
  echo "setup: installing from Debian: ${need_apt[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${need_apt[@]}"
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv"
  python3 -m venv .venv
fi
PIP=".venv/bin/python -m pip"
# The pinned packages are resolved when their lists change (or the venv is new), not on every
# rebuild: pip's resolver asks the index about pip itself and walks every requirement each time.
deps_stamp=.venv/.patina-deps
deps_key=$(cat pyproject.toml tools/requirements-build.txt | sha256sum | cut -d' ' -f1)
no_deps=--no-deps
if [ "$(cat "$deps_stamp" 2>/dev/null)" != "$deps_key" ]; then
  $PIP install -q --upgrade pip==25.1.1 >/dev/null 2>&1 || true
  # Build requirements installed once, so rebuilds need no isolated environment.
  $PIP install -q -r tools/requirements-build.txt
  no_deps=""
fi
# Built in build/cpp, the tree `make test-cpp` tests, with the C++ tests: the Release C++ is
# compiled once for the module and the tests. -Werror only when make test asks
# (PATINA_SETUP_WERROR=ON, as test-cpp configures), else what build/cpp already has, else off
# (a newer compiler's new warning must not stop `make demo`).
werror=${PATINA_SETUP_WERROR:-$(sed -n 's/^PATINA_WERROR:BOOL=//p' build/cpp/CMakeCache.txt 2>/dev/null || true)}
echo "setup: building and installing Patina into .venv"
$PIP install -q --no-build-isolation $no_deps -C build-dir=build/cpp -C cmake.define.PATINA_BUILD_TESTS=ON \
  -C cmake.define.PATINA_WERROR="${werror:-OFF}" ".[test,cluster]"
echo "$deps_key" > "$deps_stamp"

# The Khronos glTF validator (npm: the exported .gltf / .glb are checked with it in
# tests/python/export), pinned by tools/gltf_validator/package-lock.json; installed again only
# when that lock changes. Node and npm come with this machine kind; without them the test skips.
validator=tools/gltf_validator
if command -v npm >/dev/null && [ "$(cat $validator/node_modules/.patina-lock 2>/dev/null)" != "$(sha256sum < $validator/package-lock.json)" ]; then
  echo "setup: installing the glTF validator (npm) into $validator/node_modules"
  (cd $validator && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
  sha256sum < $validator/package-lock.json > $validator/node_modules/.patina-lock
fi
