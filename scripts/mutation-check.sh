#!/usr/bin/env bash
# Mutation check: applies each tests/mutations/*.patch (a deliberate rasterizer bug, described on
# the patch's first line) to a scratch copy of the working tree, rebuilds the raster and
# conformance test executables there and requires ctest to fail. Never touches the live tree.
# Prints mutation -> catching tests; exits 1 if any mutation survives, 2 on a setup error.
#
#   bash scripts/mutation-check.sh [PATCH...]      (default: every tests/mutations/*.patch)
# Environment: MUTATION_SCRATCH (default /tmp/tessera-mutation-$USER), MUTATION_LABELS
# (ctest label regex, default 'raster|conformance'), MUTATION_JOBS (build jobs, default 2),
# MUTATION_SOURCE (tree to copy, default this checkout; a non-git directory is copied whole
# except build*/).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SCRATCH=${MUTATION_SCRATCH:-/tmp/tessera-mutation-${USER:-user}}
LABELS=${MUTATION_LABELS:-raster|conformance}
JOBS=${MUTATION_JOBS:-2}
TREE=$SCRATCH            # the copy; its build/ is kept between runs (ccache keys on paths
BUILD=$SCRATCH/build     # relative to CCACHE_BASEDIR, so this layout matches an in-tree build)

if [[ $# -gt 0 ]]; then patches=("$@"); else patches=("$ROOT"/tests/mutations/*.patch); fi
[[ -e ${patches[0]} ]] || { echo "mutation-check: no patches found" >&2; exit 2; }
case $SCRATCH in "$ROOT"|"$ROOT"/*) echo "mutation-check: scratch dir must be outside the tree" >&2; exit 2 ;; esac

# 1. Scratch copy of the working tree (tracked + untracked, not ignored; deleted files skipped).
#    The copy keeps the files' mtimes, so an object compiled from a mutant is newer than the
#    restored source and would not be rebuilt: a run that did not end with the baseline rebuilt
#    (step 3's last build; interrupted, or an older version of this script) leaves the build
#    marked dirty, and the next run starts it afresh.
SOURCE=${MUTATION_SOURCE:-$ROOT}
echo "== copying $SOURCE to $TREE"
if [[ -e $BUILD/.mutant-objects ]]; then
    echo "== the last run left mutant objects: rebuilding from scratch"
    rm -rf "$BUILD"
fi
mkdir -p "$TREE" "$BUILD"
find "$TREE" -mindepth 1 -maxdepth 1 ! -name build -exec rm -rf {} +
if git -C "$SOURCE" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    (cd "$SOURCE" && git ls-files -z -c -o --exclude-standard | while IFS= read -r -d '' f; do
        [[ -e $f ]] && printf '%s\0' "$f"; done | tar --null -T - -cf -) | tar -xf - -C "$TREE"
else
    (cd "$SOURCE" && tar --exclude='./build*' -cf - .) | tar -xf - -C "$TREE"
fi

# 2. Configure and build the test executables of the labels (ccache shares objects between
#    runs and between mutations when CCACHE_BASEDIR is the scratch dir).
export CCACHE_BASEDIR=$SCRATCH
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$TREE" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DTESSERA_WERROR=ON \
    -DTESSERA_BUILD_BENCH=OFF "${launcher[@]}" >"$SCRATCH/cmake.log" 2>&1 ||
    { echo "mutation-check: cmake failed, see $SCRATCH/cmake.log" >&2; exit 2; }
# One executable per label folder (tests_<label>) or, in the older layout, one per *_test.cpp.
mapfile -t targets < <(ninja -C "$BUILD" -t targets all | sed -n 's/^\(\(tests\/\)\{0,1\}tests_[a-z_]*\): .*/\1/p' |
    grep -E "tests_(${LABELS})\$" || true)
if [[ ${#targets[@]} -eq 0 ]]; then
    for label in ${LABELS//|/ }; do
        for src in "$TREE"/tests/"$label"/*_test.cpp; do
            [[ -e $src ]] && targets+=("tests/$(basename "$src" .cpp)")
        done
    done
fi
[[ ${#targets[@]} -gt 0 ]] || { echo "mutation-check: no test targets for labels $LABELS" >&2; exit 2; }
echo "== targets: ${targets[*]}"

build() { ninja -C "$BUILD" -j "$JOBS" "${targets[@]}" >"$SCRATCH/build.log" 2>&1; }
run_tests() { (cd "$BUILD" && ctest -L "$LABELS" --output-on-failure -j 1 >"$SCRATCH/ctest.log" 2>&1); }

echo "== baseline build and tests (must pass)"
build || { echo "mutation-check: baseline build failed, see $SCRATCH/build.log" >&2; exit 2; }
run_tests || { echo "mutation-check: baseline tests fail, see $SCRATCH/ctest.log" >&2; exit 2; }

# 3. Each mutation: apply, rebuild, run, revert; then rebuild the baseline.
declare -a rows
survivors=0
touch "$BUILD/.mutant-objects"
for p in "${patches[@]}"; do
    name=$(basename "$p" .patch)
    desc=$(head -n 1 "$p")
    echo "== $name: $desc"
    if ! (cd "$TREE" && patch -p1 --forward --quiet <"$p" >/dev/null); then
        echo "mutation-check: $name does not apply" >&2; exit 2
    fi
    started=$SECONDS
    if ! build; then
        caught="build failed ($SCRATCH/build.log)"; status=ERROR
        survivors=$((survivors + 1))
    elif run_tests; then
        caught="-"; status=SURVIVED
        survivors=$((survivors + 1))
    else
        # ctest's summary lists "<n> - <test name> (Failed)"; keep the names.
        caught=$(sed -n 's/^[[:space:]]*[0-9]\{1,\} - \(.*\) (\(Failed\|SEGFAULT\|Subprocess aborted\|Exception\|Timeout\|Not Run\))$/\1/p' \
            "$SCRATCH/ctest.log" | paste -sd ',' - | sed 's/,/, /g')
        status=caught
    fi
    (cd "$TREE" && patch -p1 -R --quiet <"$p" >/dev/null)
    # The reverted files keep mutant objects in $BUILD until rebuilt; touch them so the next build
    # (next mutation, or a later run whose copy restores older mtimes) compiles the real source.
    (cd "$TREE" && sed -n 's|^+++ b/\([^[:space:]]*\).*|\1|p' "$p" | xargs -r touch)
    rows+=("$(printf '%-28s %-9s %4ss  %s' "$name" "$status" $((SECONDS - started)) "$caught")")
    echo "   $status: $caught"
done

# The reverted files are newer than their mutant objects: one build brings every object back
# to the baseline, and only then is the build clean.
build && rm -f "$BUILD/.mutant-objects"

echo
printf '%-28s %-9s %5s  %s\n' "mutation" "result" "time" "caught by (failing ctest tests)"
printf '%s\n' "${rows[@]}"
if [[ $survivors -gt 0 ]]; then
    echo "mutation-check: $survivors mutation(s) not caught" >&2
    exit 1
fi
echo "mutation-check: all ${#patches[@]} mutations caught"
