#!/usr/bin/env bash
# tools/farm-local, the farm without Slurm (fast suite): bad input fails before anything runs; 3
# tasks render tests/farm/path12.toml at 4 spp; after losing one frame and finding another's
# temporaries (as a crashed task leaves them), the same command renders that frame alone and
# removes them; every frame equals one `meso render` process bit for bit.
#   bash tests/farm/farm_local_test.sh [MESO]
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
meso=$(realpath "${1:-$src/build/meso}")
work=$(mktemp -d /tmp/meso-farm-local-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*"
  for f in "$work"/out/*.farm/logs/*.log; do [[ -f $f ]] && { echo "--- $f"; cat "$f"; }; done
  exit 1
}
command -v jq >/dev/null || fail "jq is not installed (bash tools/install-deps)"
export MESO_CACHE_DIR=$work/cache
scene=$src/tests/farm/path12.toml
out=$work/out/path12.exr
local=("$src/tools/farm-local")

rc=0
err=$("${local[@]}" "$scene" "$work/out" 0 --meso "$meso" 2>&1 >/dev/null) || rc=$?
[[ $rc -eq 2 && $err == *"TASKS: expected 1 <= TASKS <= 12"* ]] || fail "TASKS 0: exit $rc, \"$err\""
rc=0
err=$("${local[@]}" "$work/none.toml" "$out" 3 --meso "$meso" 2>&1 >/dev/null) || rc=$?
[[ $rc -eq 2 && $err == *"$work/none.toml: no such scene file"* ]] || fail "missing scene: exit $rc, \"$err\""
[[ ! -e $work/out/path12.farm ]] || fail "bad input left a farm folder"

"${local[@]}" "$scene" "$out" 3 --cpus 1 --meso "$meso" -- --spp 4 > "$work/run1.log" || fail "first run failed"
summary=$work/out/path12.farm/summary.json
[[ $(jq '.present' "$summary") -eq 12 && $(jq '.frames_with_stats' "$summary") -eq 12 ]] || fail "first run: $(cat "$summary")"
[[ $(jq '.tables_built' "$summary") -eq 0 ]] || fail "a task built tables"

rm "$work/out/path12_0007.png"
touch "$work/out/.path12_0005.tmp-999999-0.exr" "$work/out/path12.farm/stats/.path12_0005.tmp-999999-1.json"
before=$(stat -c '%i %Y' "$work/out/path12_0005.exr")
"${local[@]}" "$scene" "$out" 3 --cpus 1 --meso "$meso" -- --spp 4 > "$work/run2.log" || fail "second run failed"
grep -q "task 1/3 attempt 0 done: 1 frames rendered, 3 complete on disk" "$work/out/path12.farm/logs/task_1.log" ||
  fail "the rerun of task 1 did not render frame 7 alone"
grep -q "task 2: removed 2 temporaries" "$work/out/path12.farm/logs/task_2.log" || fail "task 2 left the temporaries"
[[ $(stat -c '%i %Y' "$work/out/path12_0005.exr") == "$before" ]] || fail "frame 5 was rendered again"
[[ -z $(find "$work/out" -name '*.tmp-*') ]] || fail "temporaries left: $(find "$work/out" -name '*.tmp-*')"

"$meso" render "$scene" -o "$work/ref/path12.exr" --spp 4 -q
for f in $(seq 0 11); do
  name=$(printf 'path12_%04d' "$f")
  cmp -s "$work/ref/$name.exr" "$work/out/$name.exr" || fail "$name.exr differs from one meso render process"
  cmp -s "$work/ref/$name.png" "$work/out/$name.png" || fail "$name.png differs from one meso render process"
done
echo "farm-local: 12 frames in 3 tasks, one frame redone after a simulated crash, bit-identical to one process"
