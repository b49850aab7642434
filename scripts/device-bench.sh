#!/usr/bin/env bash
# Runs on a lent GPU machine, over a copy of the working tree with scripts/device-prepare.sh's
# output carried: registers NVIDIA's OpenCL driver with the loader (in a private vendors folder,
# not /etc), then `plimsoll bench` (one body per size on every device, the exact clip, the
# 1000-body batch with upload, kernel and read-back apart) and `plimsoll bench --realtime` (the
# fast CPU path beside OpenCL, at rest, moving and on waves, one body and 1000). Results go under
# $OUT (or device_out/): accuracy/bench.csv, realtime/realtime.csv, and one log per bench.
# A copy of ../shared/meshes/spot.obj at build-device/spot.obj (device-prepare.sh makes it; the
# shared folder does not travel) is benchmarked beside the sphere.
# BIN names the build of the CLI (default build-device/editor/plimsoll); where
# build-device/before/plimsoll was carried too (device-prepare.sh's BEFORE=), both run, this
# build's benches then the other's, under $OUT/now and $OUT/before. METHODS: the realtime
# bench's methods (default "OpenCL,fast CPU"). BENCHES: which benches (default "accuracy
# realtime"). ROUNDS: how many times the whole A/B runs, the builds' order swapped each round
# (default 1; round r > 1 writes under $OUT/r<r>/): a second reading of the noise, same call.
#   scripts/device-bench.sh [bench sizes, default 128,2048,4096] [realtime sizes, default
#                            128,2048] [realtime frames, default 20]
set -uo pipefail
cd "$(dirname "$0")/.."
sizes=${1:-128,2048,4096}
realtimeSizes=${2:-128,2048}
frames=${3:-20}
out=${OUT:-device_out}
mkdir -p "$out"
bin=${BIN:-build-device/editor/plimsoll}
methods=${METHODS:-OpenCL,fast CPU}
export LD_LIBRARY_PATH=$PWD/build-device/devlibs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
# The loader: the machine's own when it has one, else ours.
ldconfig -p 2>/dev/null | grep -q 'libOpenCL.so.1 ' ||
  export LD_LIBRARY_PATH=$LD_LIBRARY_PATH:$PWD/build-device/devlibs/opencl
driver=""
for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib; do
  [ -e "$d/libnvidia-opencl.so.1" ] && { driver=$d/libnvidia-opencl.so.1; break; }
done
[ -n "$driver" ] || driver=$(find /usr /opt /lib -name 'libnvidia-opencl.so.1' 2>/dev/null | head -1)
echo "device-bench: NVIDIA OpenCL driver: ${driver:-none found}"
vendors=$(mktemp -d)
[ -n "$driver" ] && echo "$driver" >"$vendors/nvidia.icd"
ls /etc/OpenCL/vendors/*.icd >/dev/null 2>&1 && cp /etc/OpenCL/vendors/*.icd "$vendors/"
export OCL_ICD_VENDORS=$vendors
nvidia-smi -L 2>&1 | head -2
nproc
which=${BENCHES:-accuracy realtime}
rounds=${ROUNDS:-1}
benches() {  # binary, output folder
  mkdir -p "$2"
  local start
  if [[ " $which " == *" accuracy "* ]]; then
    start=$(date +%s)
    timeout 150 "$1" bench --sizes "$sizes" --frames 20 --mesh build-device/spot.obj --out "$2/accuracy" 2>&1 | tee "$2/accuracy.log"
    echo "device-bench: $1: bench took $(( $(date +%s) - start )) s"
  fi
  if [[ " $which " == *" realtime "* ]]; then
    start=$(date +%s)
    timeout 240 "$1" bench --realtime --bench-mesh sphere --method "$methods" --sizes "$realtimeSizes" \
      --bodies 1,1000 --frames "$frames" --out "$2/realtime" 2>&1 | tee "$2/realtime.log"
    echo "device-bench: $1: bench --realtime took $(( $(date +%s) - start )) s"
  fi
}
for round in $(seq 1 "$rounds"); do
  dir=$out
  [ "$round" -gt 1 ] && dir=$out/r$round
  if [ -x build-device/before/plimsoll ] && [ -z "${BIN:-}" ]; then
    echo "device-bench: round $round, beside the build of $(cat build-device/before/revision 2>/dev/null || echo '?')"
    if (( round % 2 )); then
      benches "$bin" "$dir/now"
      benches build-device/before/plimsoll "$dir/before"
    else  # the other order, so a drift in the machine does not favour one build
      benches build-device/before/plimsoll "$dir/before"
      benches "$bin" "$dir/now"
    fi
  else
    benches "$bin" "$dir"
  fi
done
