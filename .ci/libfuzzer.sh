#!/usr/bin/env bash
# Optional, not part of .ci/run: coverage-guided fuzzing of the scene reader with libFuzzer
# (clang 14, libfuzzer-14-dev), under AddressSanitizer and UndefinedBehaviorSanitizer, for
# SECONDS (default 60). Seeds: the shipped scenes and tests/fuzz/corpus/; new inputs that reach
# new code go to build-libfuzzer/corpus/, crashes to build-libfuzzer/crash-*.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}

source .ci/install_missing.sh
install_missing clang libfuzzer-14-dev

CC=clang CXX=clang++ cmake -S . -B build-libfuzzer -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIFTOFF_SANITIZE=ON \
  -DLIFTOFF_LIBFUZZER=ON "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1" >/dev/null
cmake --build build-libfuzzer -j"$(nproc)" --target parse_scene_fuzzer

mkdir -p build-libfuzzer/corpus build-libfuzzer/seeds
cp verification/scenes/*.toml continuation/scenes/*.toml tests/fuzz/corpus/*.toml build-libfuzzer/seeds/
cd build-libfuzzer
UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ./tests/parse_scene_fuzzer corpus seeds \
  -dict=../tests/fuzz/scene.dict -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1
