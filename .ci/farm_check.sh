#!/usr/bin/env bash
# The farm check (issue 54): job templates written by `hairlod farm` are run step by step by the
# Open Job Description reference runner (openjd-cli, installed in a virtual environment), the
# simulation chunks in order and the render steps in reverse, and their frames must be
# md5-identical to one `hairlod render` of the same scene: the paper-curly groom at automatic
# levels (60 frames, 4 simulation chunks, 6 render chunks) and a crowd. A render chunk killed
# midway leaves no partial frame, and rerun gives the same frames.
#
# Usage: .ci/farm_check.sh [HAIRLOD]   (default: target/debug/hairlod, built by `cargo test`)
set -euo pipefail
cd "$(dirname "$0")/.."
hairlod="$(realpath "${1:-target/debug/hairlod}")"
venv="${TMPDIR:-/tmp}/hairlod-openjd-venv"
if ! "$venv/bin/openjd" --version >/dev/null 2>&1; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install -q openjd-cli==0.8.0
fi
openjd="$venv/bin/openjd"
work="$(mktemp -d "${TMPDIR:-/tmp}/hairlod-farm.XXXXXX")"
trap 'rm -rf "$work"' EXIT

# The frames' md5 sums of a folder, by name.
sums() { (cd "$1" && md5sum -- *.png); }

# run_job NAME: writes NAME.job.yaml for $work/NAME.toml, checks it, runs its steps with openjd,
# renders the scene in one process and compares the frames.
run_job() {
  local name=$1 scene="$work/$1.toml" job="$work/$1.job.yaml"
  "$hairlod" farm "$scene" --out "$job" --simulation-chunks 4 --render-chunks 6 \
    --cache "$work/$name.cache" --frames-out "$work/$name.frames" --hairlod "$hairlod"
  "$openjd" check "$job"
  for k in 1 2 3 4; do
    "$openjd" run "$job" --step "Simulate-$k" --no-run-dependencies >"$work/$name.log" 2>&1 \
      || { cat "$work/$name.log"; echo "Simulate-$k failed" >&2; exit 1; }
  done
  for k in 4 3 2 1; do
    grep -q "name: \"Render-$k\"" "$job" || continue
    "$openjd" run "$job" --step "Render-$k" --no-run-dependencies >"$work/$name.log" 2>&1 \
      || { cat "$work/$name.log"; echo "Render-$k failed" >&2; exit 1; }
  done
  "$hairlod" render "$scene" --out "$work/$name.straight" 2>"$work/$name.log" \
    || { cat "$work/$name.log"; exit 1; }
  if ! diff <(sums "$work/$name.straight") <(sums "$work/$name.frames"); then
    echo "$name: the OpenJD job's frames differ from one hairlod render" >&2
    exit 1
  fi
  echo "$name: $(ls "$work/$name.frames"/*.png | wc -l) frames from the OpenJD job, md5-identical to one render"
}

cat >"$work/paper-curly.toml" <<'SCENE'
version = 2
[groom]
preset = "paper-curly"
[camera]
path = "zoom-out"
distance = 0.45
end_distance = 8.0
[motion]
kind = "shake"
[lod]
mode = "auto"
pixel_tolerance = 2.0
[frames]
count = 60
fps = 60.0
size = "320x180"
SCENE
run_job paper-curly

# A chunk count out of the template's range is refused by the runner, naming it.
if refusal=$("$openjd" run "$work/paper-curly.job.yaml" --step Simulate-1 -p RenderChunks=7 2>&1); then
  echo "openjd ran a job with 7 render chunks in a template of 6" >&2
  exit 1
fi
grep -q "RenderChunks must be at most 6" <<<"$refusal" \
  || { echo "unexpected refusal: $refusal" >&2; exit 1; }

# The crowd's grooms are grown, not hung (each of the job's nine processes builds them).
cat >"$work/crowd.toml" <<'SCENE'
version = 2
[groom]
rest_pose = "grown"
[dynamics]
settle_seconds = 0.0
[camera]
path = "orbit"
distance = 2.5
[lod]
mode = "auto"
pixel_tolerance = 2.0
[frames]
count = 12
fps = 60.0
size = "320x180"
[[character]]
position = [0.0, 0.0, 0.0]
groom = { preset = "curly" }
motion = { kind = "shake", amplitude_degrees = 20.0, peak_speed = 3.0 }
[[character]]
position = [0.5, 0.0, -0.4]
groom = { preset = "straight" }
wind = { speed = 3.0, gusts = 2.0, seed = 1 }
[[character]]
position = [-0.5, 0.0, -0.8]
groom = { preset = "wavy" }
motion = { kind = "nod" }
SCENE
run_job crowd

# A render chunk killed after its first frame: what it left is whole, and rerun it gives the
# same frames and leaves no temporary file.
killed="$work/killed"
"$hairlod" render "$work/paper-curly.toml" --from-cache "$work/paper-curly.cache" \
  --out "$killed" --chunk 2/6 2>/dev/null &
pid=$!
for _ in $(seq 1 600); do
  [ -f "$killed/frame_00010.png" ] && break
  sleep 0.1
done
kill -9 "$pid" 2>/dev/null || true
wait "$pid" 2>/dev/null || true
left=$(ls "$killed"/frame_*.png 2>/dev/null | wc -l)
for frame in "$killed"/frame_*.png; do
  [ -e "$frame" ] || continue
  cmp -s "$frame" "$work/paper-curly.straight/$(basename "$frame")" \
    || { echo "the killed chunk left a partial $(basename "$frame")" >&2; exit 1; }
done
"$hairlod" render "$work/paper-curly.toml" --from-cache "$work/paper-curly.cache" \
  --out "$killed" --chunk 2/6 2>/dev/null
if ls -A "$killed" | grep -q '\.tmp$'; then
  echo "the rerun chunk left temporary files: $(ls -A "$killed")" >&2
  exit 1
fi
for frame in $(seq 10 19); do
  name=$(printf 'frame_%05d.png' "$frame")
  cmp -s "$killed/$name" "$work/paper-curly.straight/$name" \
    || { echo "the rerun chunk's $name differs" >&2; exit 1; }
done
echo "a render chunk killed after $left frame(s) and rerun: the same 10 frames, nothing partial"
