#!/bin/sh
# Takes docs/play.png and docs/view.png from real runs of `grove play` and `grove view` under
# Xvfb (needs xvfb, xdotool, imagemagick and a Vulkan driver such as lavapipe).
# Usage: scripts/desktop-screenshots.sh [path/to/grove]
set -eu
GROVE=${1:-target/debug/grove}
D=:${SHOT_DISPLAY:-187}
TMP=$(mktemp -d)
mkdir -m 700 "$TMP/xdg"
export XDG_RUNTIME_DIR="$TMP/xdg"
Xvfb $D -screen 0 1280x720x24 -nolisten tcp >/dev/null 2>&1 &
XVFB=$!
trap 'kill $XVFB 2>/dev/null || true; rm -rf "$TMP"' EXIT
sleep 1
export DISPLAY=$D

# A task session: plant a few trees with clicks on the ground.
"$GROVE" play --task ray-casting-7 --participant DEMO --record "$TMP/demo.jsonl" 2>"$TMP/play.log" &
PLAY=$!
WID=$(timeout 60 xdotool search --sync --onlyvisible --pid $PLAY | head -1)
sleep 12
# The Trees window scrolled down to its billboards (six wheel steps).
xdotool mousemove --window "$WID" 180 300; sleep 0.5
for _ in 1 2 3 4 5 6; do xdotool click 5; sleep 0.2; done
sleep 1
# Each step: a model button in the Trees window (broadleaf, shrub and conifer billboards), then
# a target ring on the ground (the pixel positions are the study scene's task targets seen
# from its camera).
for step in "115 271 764 346" "115 439 520 354" "115 355 640 386"; do
  set -- $step
  xdotool mousemove --window "$WID" "$1" "$2"; sleep 0.4
  xdotool click 1; sleep 1
  xdotool mousemove --window "$WID" "$3" "$4"; sleep 0.4
  xdotool mousemove --window "$WID" $(($3 + 2)) "$4"; sleep 0.6
  xdotool click 1; sleep 1.5
done
xdotool mousemove --window "$WID" 880 560; sleep 2
import -window root docs/play.png
# Escape asks whether to quit during a task; Enter says yes.
xdotool windowfocus --sync "$WID"; xdotool key Escape; sleep 1; xdotool key Return
wait $PLAY

# The viewer on that recording, paused in the middle.
"$GROVE" view "$TMP/demo.jsonl" --at 100000 2>"$TMP/view.log" &
VIEW=$!
WID=$(timeout 60 xdotool search --sync --onlyvisible --pid $VIEW | head -1)
sleep 10
import -window root docs/view.png
xdotool windowfocus --sync "$WID"; xdotool key Escape
wait $VIEW
echo "wrote docs/play.png and docs/view.png"
