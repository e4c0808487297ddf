#!/usr/bin/env bash
# The figures of the open targets that need the device machine (an H100 or H200 and 16 CPU
# cores), in one command that fits one device call: see README.md beside this file.
#
#   studies/device-targets/run.sh [BIN] [OUTDIR]
#
# BIN: the cleave binary (default .dev/cleave, as prepare.sh leaves it); OUTDIR: where each
# run's output and the summary `targets.txt` go (default $OUT, else device-targets.out).
# QUICK=1 runs every case at a small size, for a check of the script on any machine (lavapipe).
# CASES="NAME ..." runs only the cases named (all by default); FULL_LIMIT: the seconds the
# paper's full run may take (125 by default; the time it reached says its speed).
# Each case has a time limit; together they come to at most 560 s, so one device call with
# timeout_s 600 holds them all (a case stopped at its limit says so in the summary).
set -uo pipefail
cd "$(dirname "$0")/../.."
bin="${1:-.dev/cleave}"
out="${2:-${OUT:-device-targets.out}}"
mkdir -p "$out"
summary="$out/targets.txt"
: >"$summary"

# the Vulkan loader where the machine has none (prepare.sh downloaded it into .gl)
# and the GL dispatch libraries (libglvnd) that NVIDIA's Vulkan driver, libGLX_nvidia, needs: without
# them the loader finds the driver but "Could not get 'vkCreateInstance'" and wgpu no adapter
if [ -d .gl ] && ! { ldconfig -p | grep -q libvulkan && ldconfig -p | grep -q libGLdispatch; } 2>/dev/null; then
  for f in .gl/*.deb; do dpkg -x "$f" / >/dev/null; done
  ldconfig
fi
nv=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -f "$nv" ]; then export VK_DRIVER_FILES="$nv"; fi
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
threads=$(nproc)

if [ "${QUICK:-0}" = 1 ]; then
  cube_big=8000 cube_mid=1000 cube_steps=50 ball=256 ball_big=2800 ball_big_end=2e-6 cpu_cube=8000
  full_end=2e-5 limit=60
else
  cube_big=1000000 cube_mid=100000 cube_steps=3000 ball=20000 ball_big=160000 ball_big_end=5e-6
  cpu_cube=1000000 full_end=1e-2 limit=${FULL_LIMIT:-125}
fi

# one case: its name, the time allowed (s), the command; its output to OUTDIR/NAME.txt and
# the lines with the figures to the summary
case_() {
  local name=$1 secs=$2
  shift 2
  if [ -n "${CASES:-}" ] && ! [[ " $CASES " == *" $name "* ]]; then return; fi
  echo "== $name: $*" | tee -a "$summary"
  local t0=$SECONDS
  timeout "$secs" "$@" >"$out/$name.txt" 2>&1
  local rc=$?
  grep -E "us per|ns\)|ns per|idle|device memory|halted|split's|passes|shares|contact phases|interface checks [0-9]|peak|interfaces failed|elements \(|stopped" \
    "$out/$name.txt" | head -14 | tee -a "$summary"
  echo "   exit $rc after $((SECONDS - t0)) s$([ $rc = 124 ] && echo " (stopped at its limit of $secs s)")" \
    | tee -a "$summary"
}

{
  echo "cleave device targets, $(date -u +%F\ %T) UTC, $(nproc) CPUs"
  "$bin" --version 2>/dev/null
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null
} | tee -a "$summary"

# issue 30: the GPU step
# issue 30: the GPU step
case_ gpu-cube-1m 30 "$bin" bench cube --elements $cube_big --steps $cube_steps --gpu
case_ gpu-cube-100k 20 "$bin" bench cube --elements $cube_mid --steps $((cube_steps * 3)) --gpu
case_ gpu-ball-20k 85 "$bin" bench ball --elements $ball --gpu
case_ gpu-ball-20k-passes 20 "$bin" bench ball --elements $ball --end-time 5e-6 --gpu --passes
case_ gpu-ball-2800-passes 30 "$bin" bench ball --elements 2800 --end-time 2e-5 --gpu --passes
# the contact's candidate lists (64 faces a node by default; any length gives the same
# results): none, every node against its grid cell every step, against the default
case_ gpu-ball-2800-no-lists 30 env CLEAVE_GPU_CANDS=0 "$bin" bench ball --elements 2800 \
  --end-time 2e-5 --gpu --passes
# the paper's full run of the 2800 ball on the GPU: target under 2 minutes
if [ -z "${CASES:-}" ] || [[ " $CASES " == *" gpu-ball-2800-full "* ]]; then
  "$bin" example ball-impact -o "$out/ball.k" --end-time $full_end >/dev/null
fi
case_ gpu-ball-2800-full $limit "$bin" run "$out/ball.k" --gpu --quiet -o "$out/ball-run"
rm -rf "$out/ball-run"

# issue 34: the fragmenting run on every core
case_ cpu-ball-160k-1 90 "$bin" bench ball --elements $ball_big --end-time $ball_big_end --threads 1
case_ cpu-ball-160k-all 30 "$bin" bench ball --elements $ball_big --end-time $ball_big_end --threads "$threads"
case_ cpu-cube-1m-1 30 "$bin" bench cube --elements $cpu_cube --steps 20 --threads 1
case_ cpu-cube-1m-all 45 "$bin" bench cube --elements $cpu_cube --steps 200 --threads "$threads"
echo "done" | tee -a "$summary"
