#!/usr/bin/env bash
# Usage: tests/fuzz/run_fuzz.sh [SECONDS]   (default 60)
# Configures and builds the libFuzzer target in build-fuzz/ (clang-14, -DSCULPT_FUZZ=ON), then fuzzes
# the OBJ reader/writer on a temporary copy of tests/fuzz/corpus (the repository stays clean). Any
# crash, leak, timeout or out-of-memory input is copied to tests/io/data/fuzz_regressions/, which the
# unit test "obj: fuzz regressions ..." replays, and the script exits non-zero.
set -euo pipefail

seconds="${1:-60}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$root/build-fuzz"
regressions="$root/tests/io/data/fuzz_regressions"

CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -DSCULPT_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" --target obj_fuzz -j2

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp -r "$root/tests/fuzz/corpus" "$work/corpus"
mkdir "$work/artifacts"

status=0
# -timeout: any single input slower than 10 s is a bug (files here are at most 4 KiB).
"$build/tests/fuzz/obj_fuzz" -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -dict="$root/tests/fuzz/obj.dict" -artifact_prefix="$work/artifacts/" -print_final_stats=1 \
    "$work/corpus" || status=$?

shopt -s nullglob
found=("$work"/artifacts/*)
if [ "$status" -ne 0 ] || [ "${#found[@]}" -gt 0 ]; then
    mkdir -p "$regressions"
    for input in "${found[@]}"; do
        cp "$input" "$regressions/"
        echo "run_fuzz.sh: saved $(basename "$input") to tests/io/data/fuzz_regressions/" >&2
    done
    echo "run_fuzz.sh: the fuzzer failed (exit $status)" >&2
    exit 1
fi
echo "run_fuzz.sh: no failures in ${seconds} s"
