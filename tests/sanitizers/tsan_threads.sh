#!/usr/bin/env bash
# ThreadSanitizer on the particle engines' threads without a whole sanitizer build: compiles the sources of
# particle/common (the worker pool), particle/dem, particle/ts and particle/dsmc with clang++
# -fsanitize=thread, links them with tests/sanitizers/threads.cpp against the plain build's analysis and
# solvers libraries (BUILD_DIR, default build/; their code runs on the threads uninstrumented, so a race
# inside them would go unseen), and runs it; then the worker pool's unit tests
# (tests/particle/common/test_worker_pool.cpp, Catch2) built the same way. Exit status: 0 when both are
# clean, else non-zero (a TSan report exits 66).
#   tests/sanitizers/tsan_threads.sh            (objects kept in build-tsan-threads/, ccache if present)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${BUILD_DIR:-build}
out=build-tsan-threads
mkdir -p "$out"
[ -f "$build/analysis/libaggkit_analysis.so" ] || { echo "tsan_threads.sh: build $build first (scripts/setup)" >&2; exit 2; }
if ! command -v clang++ >/dev/null || [ ! -f "$(clang++ -print-resource-dir)/lib/linux/libclang_rt.tsan-x86_64.a" ]; then
  # clang and its sanitizer runtimes are not among scripts/setup's packages (only the sanitizer checks need them).
  echo "tsan_threads.sh: installing clang and libclang-rt-14-dev (Debian)"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q clang libclang-rt-14-dev >/dev/null
fi
launcher=""
command -v ccache >/dev/null && launcher=ccache
flags="-std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=thread -I. -I/usr/include/eigen3"
sources=(particle/common/*.cpp particle/dem/*.cpp particle/ts/*.cpp particle/dsmc/*.cpp tests/sanitizers/threads.cpp
         tests/particle/common/test_worker_pool.cpp)
printf '%s\n' "${sources[@]}" | xargs -P "$(nproc)" -I{} sh -c \
  'o='"$out"'/$(echo {} | tr / _).o; '"$launcher"' clang++ '"$flags"' -c {} -o "$o"'
libraries=(-L"$build/analysis" -L"$build/solvers" -Wl,-rpath,"$PWD/$build/analysis:$PWD/$build/solvers"
           -laggkit_solvers -laggkit_analysis $(pkg-config --libs gsl) -lpthread)
driver=()  # every object but the worker pool tests' (they have their own main, Catch2's)
for object in "$out"/*.o; do [[ $object == *test_worker_pool* ]] || driver+=("$object"); done
clang++ -fsanitize=thread "${driver[@]}" -o "$out/threads" "${libraries[@]}"
clang++ -fsanitize=thread "$out"/particle_common_*.o "$out"/tests_particle_common_test_worker_pool.cpp.o \
  /usr/lib/libCatch2WithMain.a -o "$out/worker_pool_tests" "${libraries[@]}"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/sanitizers/tsan.supp"
"$out/threads"
"$out/worker_pool_tests"
