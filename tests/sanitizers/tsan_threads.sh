#!/usr/bin/env bash
# ThreadSanitizer on the particle engines' threads without a whole sanitizer build: compiles the sources of
# particle/common (the worker pool), particle/dem, particle/ts and particle/dsmc with clang++
# -fsanitize=thread, links them with tests/sanitizers/threads.cpp against the plain build's analysis and
# solvers libraries (BUILD_DIR, default build/; their code runs on the threads uninstrumented, so a race
# inside them would go unseen), and runs it. Exit status: the driver's (0 clean; TSan reports exit 66).
#   tests/sanitizers/tsan_threads.sh            (objects kept in build-tsan-threads/, ccache if present)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${BUILD_DIR:-build}
out=build-tsan-threads
mkdir -p "$out"
[ -f "$build/analysis/libaggkit_analysis.so" ] || { echo "tsan_threads.sh: build $build first (scripts/setup)" >&2; exit 2; }
launcher=""
command -v ccache >/dev/null && launcher=ccache
flags="-std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=thread -I. -I/usr/include/eigen3"
sources=(particle/common/*.cpp particle/dem/*.cpp particle/ts/*.cpp particle/dsmc/*.cpp tests/sanitizers/threads.cpp)
printf '%s\n' "${sources[@]}" | xargs -P "$(nproc)" -I{} sh -c \
  'o='"$out"'/$(echo {} | tr / _).o; '"$launcher"' clang++ '"$flags"' -c {} -o "$o"'
clang++ -fsanitize=thread "$out"/*.o -o "$out/threads" -L"$build/analysis" -L"$build/solvers" \
  -Wl,-rpath,"$PWD/$build/analysis:$PWD/$build/solvers" -laggkit_solvers -laggkit_analysis \
  $(pkg-config --libs gsl) -lpthread
TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/sanitizers/tsan.supp" "$out/threads"
