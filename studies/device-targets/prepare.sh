#!/usr/bin/env bash
# Make ready, on the development machine, what run.sh needs on the device machine (which has no
# network): the release binary without its debug information (10 MB instead of 76: a device call
# carries at most 64 MiB) in .dev/, and the Vulkan loader's Debian packages in .gl/, both kept
# out of git. Then one device call: command `studies/device-targets/run.sh`, carry [".dev", ".gl"],
# timeout_s 600 (README.md beside this file).
set -euo pipefail
cd "$(dirname "$0")/../.."
cargo build --release -p cleave
mkdir -p .dev .git/info
strip -o .dev/cleave target/release/cleave
for d in /.dev/ /.gl/; do grep -qxF "$d" .git/info/exclude 2>/dev/null || echo "$d" >>.git/info/exclude; done
if ! ls .gl/libvulkan1_*.deb .gl/libglvnd0_*.deb >/dev/null 2>&1; then
  mkdir -p .gl /tmp/amd64/partial
  o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
  apt-get "${o[@]}" update -q >/dev/null
  (cd .gl && apt-get "${o[@]}" download libvulkan1 libglvnd0 libegl1 libgl1 libglx0 libgles2 libopengl0 >/dev/null)
fi
ls -la .dev/cleave .gl/
