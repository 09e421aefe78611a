#!/usr/bin/env bash
# Takes a screenshot of the Rerun viewer (tested with rerun 0.36.3) showing a recording's
# default layout, on a headless Linux machine without a GPU.
#
#   docs/screenshot.sh RECORDING.rrd OUT.png
#
# Needs: Xvfb (xvfb), xwd (x11-apps), xdotool, ImageMagick's convert (imagemagick),
# Mesa's lavapipe Vulkan driver (mesa-vulkan-drivers) and, optionally, pngquant.
# The viewer is `rerun` on PATH, or $RERUN (e.g. RERUN=.venv/bin/rerun from rerun-sdk).
#
# What it does: starts Xvfb at 1600x900x24 on a free display, runs the viewer there with
# wgpu's Vulkan backend on lavapipe (CPU rendering) and a private, empty HOME (so no saved
# layout from an earlier session is used), waits until the recording has finished loading
# and the window has drawn, moves the time cursor to the end of the timeline (End, then
# Space to pause), waits until the picture stops changing, grabs the window with xwd,
# writes a PNG downscaled to 1280 px wide with a 256-colour palette, and stops everything.
#
# Why Xvfb runs with `-extension Composite`: with Composite, Xvfb offers a 32-bit ARGB visual
# and the viewer (which asks for a transparent window) takes it; Mesa 22.3's lavapipe then
# presents with a depth-24 PutImage into that depth-32 window, the X server rejects it
# (BadMatch) and the window stays black. Without Composite the window gets the 24-bit root
# visual and presents fine. (wgpu's GL backend on llvmpipe does not work either: the viewer
# exits with "Adapter does not support drawing to texture format R32Float".)
#
# Environment knobs: RERUN (viewer command), SCREENSHOT_TIMEOUT (seconds to wait for the
# viewer to load and draw, default 120), SCREENSHOT_WIDTH (output width, default 1280).
set -euo pipefail

usage() { echo "usage: $0 RECORDING.rrd OUT.png" >&2; exit 2; }
die() { echo "screenshot.sh: error: $*" >&2; exit 1; }
say() { echo "screenshot.sh: $*" >&2; }

[ $# -eq 2 ] || usage
rrd=$1
out=$2
[ -f "$rrd" ] && [ -r "$rrd" ] || die "recording '$rrd' is not a readable file"
case "$out" in *.png) ;; *) die "OUT must end in .png: '$out'" ;; esac
out_dir=$(dirname -- "$out")
[ -d "$out_dir" ] || die "output folder '$out_dir' does not exist"

rerun=${RERUN:-rerun}
timeout_s=${SCREENSHOT_TIMEOUT:-120}
width=${SCREENSHOT_WIDTH:-1280}
screen_w=1600
screen_h=900

command -v "$rerun" >/dev/null 2>&1 || die "rerun viewer '$rerun' not found (set RERUN=/path/to/venv/bin/rerun)"
for tool in Xvfb xwd xdotool convert; do
  command -v "$tool" >/dev/null 2>&1 || die "'$tool' not found (apt-get install -y --no-install-recommends xvfb x11-apps xdotool imagemagick)"
done
convert -version 2>/dev/null | grep -q ImageMagick || die "'convert' is not ImageMagick (apt-get install -y --no-install-recommends imagemagick)"
lvp_icd=
for f in /usr/share/vulkan/icd.d/lvp_icd.*.json; do
  [ -f "$f" ] && lvp_icd=$f && break
done
[ -n "$lvp_icd" ] || die "Mesa's lavapipe Vulkan driver not found (apt-get install -y --no-install-recommends mesa-vulkan-drivers)"

start=$(date +%s)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/rerun-shot.XXXXXX")
chmod 700 "$tmp"
xvfb_pid=
viewer_pid=

cleanup() {
  local rc=$?
  if [ -n "$viewer_pid" ]; then
    # setsid made the viewer (and the rerun-sdk wrapper's child) a process group of its own
    kill -TERM -- "-$viewer_pid" 2>/dev/null || true
    for _ in 1 2 3 4 5 6 7 8 9 10; do kill -0 -- "-$viewer_pid" 2>/dev/null || break; sleep 0.5; done
    kill -KILL -- "-$viewer_pid" 2>/dev/null || true
    wait "$viewer_pid" 2>/dev/null || true
  fi
  if [ -n "$xvfb_pid" ]; then
    kill -TERM "$xvfb_pid" 2>/dev/null || true
    wait "$xvfb_pid" 2>/dev/null || true
  fi
  if [ $rc -ne 0 ] && [ -s "$tmp/viewer.log" ]; then
    echo "screenshot.sh: last lines of the viewer's log:" >&2
    sed 's/\x1b\[[0-9;]*m//g' "$tmp/viewer.log" | tail -n 15 >&2
  fi
  rm -rf -- "$tmp"
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT TERM

deadline=$((start + timeout_s))
time_left() { [ "$(date +%s)" -lt "$deadline" ]; }
viewer_alive() { kill -0 "$viewer_pid" 2>/dev/null; }

# --- X server on a free display (Xvfb picks it and writes its number to fd 3) ---
Xvfb -displayfd 3 -screen 0 "${screen_w}x${screen_h}x24" -nolisten tcp -extension Composite \
  3>"$tmp/display" >"$tmp/xvfb.log" 2>&1 &
xvfb_pid=$!
until [ -s "$tmp/display" ] && grep -q . "$tmp/display"; do
  kill -0 "$xvfb_pid" 2>/dev/null || die "Xvfb exited: $(tail -n 5 "$tmp/xvfb.log")"
  time_left || die "Xvfb did not start within ${timeout_s}s"
  sleep 0.2
done
export DISPLAY=":$(head -n 1 "$tmp/display" | tr -dc 0-9)"
say "Xvfb on $DISPLAY (${screen_w}x${screen_h}x24)"

# --- the viewer, with a private HOME and runtime dir, on lavapipe ---
mkdir -m 700 "$tmp/home" "$tmp/runtime"
export HOME="$tmp/home" XDG_RUNTIME_DIR="$tmp/runtime"
export XDG_CONFIG_HOME="$HOME/.config" XDG_DATA_HOME="$HOME/.local/share" XDG_CACHE_HOME="$HOME/.cache"
export WGPU_BACKEND=vulkan VK_ICD_FILENAMES="$lvp_icd"
# re_viewer::app::logic logs "Data source ... has finished" at debug level once the file is loaded.
export RUST_LOG="warn,re_viewer::app::logic=debug"
"$rerun" analytics disable >/dev/null 2>&1 || true # no first-run banner, no network attempts

setsid "$rerun" --new --bind 127.0.0.1 --window-size "${screen_w}x${screen_h}" "$rrd" \
  </dev/null >"$tmp/viewer.log" 2>&1 &
viewer_pid=$!

window=
until [ -n "$window" ]; do
  viewer_alive || die "the viewer exited before opening a window"
  time_left || die "the viewer opened no window within ${timeout_s}s"
  sleep 0.5
  window=$(xdotool search --onlyvisible --name '^Rerun' 2>/dev/null | head -n 1 || true)
done
say "viewer window $window is up after $(($(date +%s) - start))s; waiting for the recording to load"

until grep -q 'has finished' "$tmp/viewer.log"; do
  viewer_alive || die "the viewer exited while loading '$rrd'"
  ! grep -q 'ERROR' "$tmp/viewer.log" || die "the viewer could not load '$rrd'"
  time_left || die "the recording did not finish loading within ${timeout_s}s"
  sleep 0.5
done
! grep -q 'ERROR' "$tmp/viewer.log" || die "the viewer could not load '$rrd'"

capture() { xwd -silent -id "$window" >"$1" 2>/dev/null; }
# standard deviation of the picture's pixels: 0 for a black (not yet drawn) window
spread() { convert "xwd:$1" -colorspace Gray -format '%[fx:standard_deviation]' info: 2>/dev/null || echo 0; }

until capture "$tmp/a.xwd" && awk -v s="$(spread "$tmp/a.xwd")" 'BEGIN { exit !(s > 0.02) }'; do
  viewer_alive || die "the viewer exited before drawing"
  time_left || die "the viewer window stayed blank for ${timeout_s}s (software rendering broken?)"
  sleep 1
done
say "first frame drawn after $(($(date +%s) - start))s"

# Time cursor to the end of the timeline: End follows the newest data, Space pauses there.
# Then park the pointer on the empty middle of the top bar, so that nothing shows a hover.
xdotool windowfocus "$window"
xdotool key End
sleep 1
xdotool key space
xdotool mousemove $((screen_w / 2)) 12

# Wait until two captures two seconds apart are the same: the viewer has settled.
prev=
while :; do
  sleep 2
  viewer_alive || die "the viewer exited before settling"
  capture "$tmp/a.xwd" || die "xwd could not capture window $window on $DISPLAY"
  sum=$(convert "xwd:$tmp/a.xwd" rgb:- | md5sum | cut -d' ' -f1)
  [ "$sum" = "$prev" ] && break
  prev=$sum
  time_left || die "the viewer's picture did not settle within ${timeout_s}s"
done

# --- PNG: downscaled, 256 colours ---
convert "xwd:$tmp/a.xwd" -alpha off -resize "${width}x" "$tmp/full.png" || die "convert failed"
if command -v pngquant >/dev/null 2>&1; then
  pngquant --force --strip --speed 1 --output "$tmp/small.png" 256 -- "$tmp/full.png" \
    || die "pngquant failed"
else
  convert "$tmp/full.png" -dither FloydSteinberg -colors 256 -strip "PNG8:$tmp/small.png" \
    || die "convert -colors failed"
fi
mv -f -- "$tmp/small.png" "$out"
size=$(stat -c %s "$out")
say "wrote $out ($size bytes, $(identify -format '%wx%h' "$out")) in $(($(date +%s) - start))s"
[ "$size" -le 409600 ] || say "warning: $out is larger than 400 KB"
