#!/usr/bin/env bash
# The render farm against a real Slurm (issue 19): starts a one-node cluster on this machine
# (tests/farm/one_node_slurm.sh), checks that bad input fails before anything is submitted, submits
# tests/farm/path12.toml (12 frames at 160x90) as 3 tasks with tools/meso-farm, SIGKILLs one task's
# meso in the middle of a frame, requeues the task with scontrol, and checks that every frame is
# there exactly once, bit for bit the frames of a single-process render, with no temporary file
# left, the tables built once (by the first job) and the frames finished before the kill untouched.
#   bash tests/farm/farm_slurm_test.sh [MESO]      exit 77 (CTest: skipped) without Slurm or munge
# MESO_FARM_TEST_KEEP=1 keeps the temporary folder (frames, farm logs, Slurm's logs).
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
meso=$(realpath "${1:-$src/build/meso}")
farm=$src/tools/meso-farm
source "$src/tests/farm/one_node_slurm.sh"

if ! missing=$(slurmPackagesPresent); then
  echo "SKIP: $missing is not installed: the farm test needs Debian's slurmctld, slurmd, slurm-client and munge (bash tools/install-deps)"
  exit 77
fi
if [[ $(id -u) -ne 0 ]]; then
  echo "SKIP: the farm test runs slurmd, which needs root (CI runs as root)"
  exit 77
fi
command -v jq >/dev/null || { echo "FAIL: jq is not installed (bash tools/install-deps)"; exit 1; }

testStart=$EPOCHREALTIME
work=$(mktemp -d /tmp/meso-farm-test.XXXXXX)
cleanup() {
  local rc=$?
  slurmStop
  if [[ $rc -ne 0 && -d $work/out ]]; then
    for f in "$work"/out/*.farm/logs/*.log; do [[ -f $f ]] && { echo "--- $f"; cat "$f"; }; done
    slurmLogs
  fi
  if [[ -n ${MESO_FARM_TEST_KEEP:-} ]]; then echo "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*"
  exit 1
}
elapsed() { awk "BEGIN { printf \"%.1f\", $EPOCHREALTIME - $1 }"; }
jobCount() { scontrol -o show job 2>/dev/null | grep -c '^JobId=' || true; }
jobState() { scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | head -1 | cut -d= -f2; }
waitState() {  # JOB SECONDS STATE...: waits until the job is in one of the states
  local job=$1 seconds=$2 state
  shift 2
  for _ in $(seq 1 $((seconds * 10))); do
    state=$(jobState "$job")
    for s in "$@"; do [[ $state == "$s" ]] && return 0; done
    sleep 0.1
  done
  fail "job $job is $state after $seconds s, expected $*"
}

slurmStart "$work/slurm" || fail "could not start a one-node Slurm"
echo "slurm: one node up ($(sinfo -h -o '%N %c CPUs %T'))"

scene=$src/tests/farm/path12.toml
out=$work/out/path12.exr
spp=256  # about 1 s a frame: long enough to kill a task inside one
export MESO_CACHE_DIR=$work/cache  # the shared table cache that meso-farm hands to every job

# --- bad input: a located message, exit 2, nothing submitted ---
expectBad() {  # MESSAGE ARGS...
  local message=$1 err rc=0
  shift
  err=$("$farm" submit "$@" --meso "$meso" 2>&1 >/dev/null) || rc=$?
  [[ $rc -eq 2 ]] || fail "meso-farm submit $* exited $rc, expected 2 ($err)"
  [[ $err == *"$message"* ]] || fail "meso-farm submit $*: expected \"$message\" in \"$err\""
  [[ $(jobCount) -eq 0 ]] || fail "meso-farm submit $*: submitted a job on bad input"
  echo "bad input, nothing submitted: $err"
}
touch "$work/a-file"
printf '[camera]\nspp = "many"\n' > "$work/bad.toml"
expectBad "$work/none.toml: no such scene file" "$work/none.toml" "$out" 3
expectBad "$work/bad.toml:2:7: camera.spp: expected an integer" "$work/bad.toml" "$out" 3
expectBad "$work/a-file/out: cannot create the output folder" "$scene" "$work/a-file/out/path12.exr" 3
expectBad "--shards: expected shards i with 0 <= i < 3, got \"3\"" "$scene" "$out" 3 --shards 0,3
expectBad "TASKS: expected 1 <= TASKS <= 12" "$scene" "$out" 13
expectBad "--frames: expected A:B with 0 <= A <= B < 12" "$scene" "$out" 3 --frames 4:12
expectBad "--spp: Value 0 not in range" "$scene" "$out" 3 -- --spp 0
[[ ! -e $work/out/path12.farm ]] || fail "bad input left a farm folder"

# --- the job array, one task killed mid-frame and requeued ---
submitted=$EPOCHREALTIME
line=$("$farm" submit "$scene" "$out" 3 --cpus 1 --meso "$meso" -- --spp "$spp" | tail -1)
eval "$line"  # tables=ID frames=ID gather=ID
[[ -n ${tables:-} && -n ${frames:-} && -n ${gather:-} ]] || fail "meso-farm submit printed \"$line\""
echo "submitted: $line"
# Hold the final job while the killed task is requeued: were the other tasks all done by then,
# afterany would let it start before the requeue. An operator does the same.
scontrol hold "$gather"

victim=1 victimFrame=4  # task 1 renders frames 1, 4, 7, 10: kill it inside its second frame
done1=$work/out/path12_0001
pid=""
for _ in $(seq 1 1200); do
  pid=$(pgrep -f -- "--frames $victimFrame:$victimFrame --shard $victim/3" || true)
  [[ -n $pid ]] && break
  sleep 0.1
done
[[ -n $pid ]] || fail "task $victim never started frame $victimFrame"
sleep 0.9  # past start-up (process, scene, tables from the cache: about 0.5 s), inside the render (over 1 s)
before=$(stat -c '%i %Y' "$done1.exr" "$done1.png" "$work/out/path12.farm/stats/path12_0001.json")
kill -9 "$pid" || fail "meso of task $victim (pid $pid) ended before it could be killed"
[[ ! -e $work/out/path12_000$victimFrame.exr ]] || fail "frame $victimFrame was complete: the kill missed the frame"
# A kill during the write leaves the frame's temporaries (the window is a few ms, too short to hit
# on purpose): leave two as it would, for the requeued task to remove.
touch "$work/out/.path12_000$victimFrame.tmp-999999-0.exr" "$work/out/.path12_000$victimFrame.tmp-999999-1.png"
echo "killed: meso of task $victim (pid $pid) inside frame $victimFrame"
waitState "${frames}_$victim" 60 FAILED
scontrol requeue "${frames}_$victim"
requeues=1
scontrol release "$gather"
waitState "$gather" 300 COMPLETED FAILED CANCELLED
wall=$(elapsed "$submitted")
[[ $(jobState "$gather") == COMPLETED ]] || fail "the gather job ended $(jobState "$gather")"

# --- every frame exactly once, bit-identical, nothing left over ---
summary=$work/out/path12.farm/summary.json
cat "$work/out/path12.farm/summary.txt"
[[ $(jq '.present' "$summary") -eq 12 && $(jq '.missing | length' "$summary") -eq 0 ]] || fail "frames missing"
[[ $(jq '.temporaries_removed' "$summary") -eq 0 ]] || fail "the requeued task left temporaries for gather"
[[ $(jq '.tables_built' "$summary") -eq 0 ]] || fail "a task built tables: the cache was not shared"
grep -q ',miss,' "$work/out/path12.farm/logs/tables.log" || fail "the tables job did not build the tables"
[[ $(jq -c '[.tasks[].attempts]' "$summary") == "[1,2,1]" ]] || fail "attempts $(jq -c '[.tasks[].attempts]' "$summary"), expected [1,2,1]"
[[ $(jq '.frames_with_stats' "$summary") -eq 12 ]] || fail "frames without stats"
scontrol -o show job "${frames}_$victim" | grep -q 'Restarts=1 ' || fail "task $victim was not restarted once"
grep -q "task $victim: removed 2 temporaries" "$work/out/path12.farm/logs/task_$victim.log" || fail "the requeued task did not remove the temporaries"
grep -q "task $victim/3 attempt 1 done: 3 frames rendered, 1 complete on disk" "$work/out/path12.farm/logs/task_$victim.log" ||
  fail "the requeued task did not render exactly the 3 frames it was missing"
[[ $(stat -c '%i %Y' "$done1.exr" "$done1.png" "$work/out/path12.farm/stats/path12_0001.json") == "$before" ]] ||
  fail "frame 1, complete before the kill, was written again"
video=""
if command -v ffmpeg >/dev/null; then  # the gather job assembles the video when ffmpeg is there
  [[ $(jq -r '.video' "$summary") == "$work/out/path12.mp4" ]] || fail "no video in the summary though ffmpeg is installed"
  count=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 "$work/out/path12.mp4")
  [[ $count -eq 12 ]] || fail "path12.mp4 has $count frames, expected 12"
  video=path12.mp4
  echo "video: path12.mp4, 12 frames"
fi
expected=$( (for f in $(seq 0 11); do printf 'path12_%04d.exr\npath12_%04d.png\n' "$f" "$f"; done; echo .path12.meso-settings; echo path12.farm; [[ -z $video ]] || echo "$video") | sort)
[[ $(ls -A "$work/out" | sort) == "$expected" ]] || fail "unexpected files in the output folder: $(ls -A "$work/out")"
leftover=$(find "$work/out" "$MESO_CACHE_DIR" -name '*.tmp-*')
[[ -z $leftover ]] || fail "temporary files left: $leftover"

refStart=$EPOCHREALTIME
"$meso" render "$scene" -o "$work/ref/path12.exr" --spp "$spp" -q
refWall=$(elapsed "$refStart")
for f in $(seq 0 11); do
  name=$(printf 'path12_%04d' "$f")
  cmp -s "$work/ref/$name.exr" "$work/out/$name.exr" || fail "$name.exr differs from the single-process render"
  cmp -s "$work/ref/$name.png" "$work/out/$name.png" || fail "$name.png differs from the single-process render"
done
echo "bit-identical: 12 EXR and 12 PNG frames equal those of one meso render process (${refWall} s for it)"

echo "farm test figures: tasks 3, frames 12 (160x90, $spp spp), wall time $wall s from submission to summary," \
  "requeues $requeues, seconds per frame $(jq '.seconds_per_frame.mean * 100 | round / 100' "$summary")," \
  "peak memory per task $(jq -r '[.tasks[].peak_rss_mib | round | tostring] | join("/")' "$summary") MiB," \
  "test $(elapsed "$testStart") s"
