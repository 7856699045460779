#!/usr/bin/env bash
# Usage: tests/fuzz/run_fuzz.sh [SECONDS]   (default 60)
# Configures and builds the libFuzzer targets in build-fuzz/ (clang-14, -DSCULPT_FUZZ=ON), then fuzzes, SECONDS
# each, the OBJ reader/writer on a temporary copy of tests/fuzz/corpus and the PLY/STL/glTF readers/writers on
# one of tests/fuzz/corpus_mesh, and the glTF reader structure-aware (gltf_fuzz) on tests/fuzz/corpus_gltf (the
# repository stays clean). Any crash, leak, timeout or out-of-memory input
# is copied to tests/io/data/fuzz_regressions/ (OBJ) or fuzz_regressions_mesh/, which the unit tests
# "obj: fuzz regressions ..." and "mesh formats: fuzz corpus and regressions ..." replay, and the script exits
# non-zero.
set -euo pipefail

seconds="${1:-60}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$root/build-fuzz"

# SCULPT_UNITY: the instrumented libraries compile in batches (see the top-level CMakeLists.txt).
CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -DSCULPT_FUZZ=ON -DSCULPT_UNITY=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" --target obj_fuzz mesh_fuzz gltf_fuzz -j2

# Leaks inside third-party libraries (assimp's, on malformed files) are suppressed, as in CI's sanitizer run.
export LSAN_OPTIONS="suppressions=$root/.ci/lsan.supp:print_suppressions=0"
# As in .ci/run: without it LeakSanitizer's tracer can die on a dynamic TLS block it misreads (a crash that is
# not the input's).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}intercept_tls_get_addr=0"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# fuzz TARGET CORPUS DICT REGRESSIONS: runs one target for $seconds on a copy of its corpus.
fuzz() {
    local target="$1" corpus="$2" dict="$3" regressions="$4"
    rm -rf "$work/corpus" "$work/artifacts"
    cp -r "$corpus" "$work/corpus"
    mkdir "$work/artifacts"
    local status=0
    # -timeout: any single input slower than 10 s is a bug (files here are at most 4 KiB).
    "$build/tests/fuzz/$target" -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
        ${dict:+-dict="$dict"} -artifact_prefix="$work/artifacts/" -print_final_stats=1 \
        "$work/corpus" || status=$?
    shopt -s nullglob
    local found=("$work"/artifacts/*)
    if [ "$status" -ne 0 ] || [ "${#found[@]}" -gt 0 ]; then
        mkdir -p "$regressions"
        for input in "${found[@]}"; do
            cp "$input" "$regressions/"
            echo "run_fuzz.sh: saved $(basename "$input") to ${regressions#"$root"/}/" >&2
        done
        echo "run_fuzz.sh: $target failed (exit $status)" >&2
        exit 1
    fi
    echo "run_fuzz.sh: $target: no failures in ${seconds} s"
}

fuzz obj_fuzz "$root/tests/fuzz/corpus" "$root/tests/fuzz/obj.dict" "$root/tests/io/data/fuzz_regressions"
fuzz mesh_fuzz "$root/tests/fuzz/corpus_mesh" "" "$root/tests/io/data/fuzz_regressions_mesh"
fuzz gltf_fuzz "$root/tests/fuzz/corpus_gltf" "" "$root/tests/io/data/fuzz_regressions_mesh"
