#!/usr/bin/env bash
# Failures of the environment, through the `aamap` command:
#   no-device    no Vulkan driver at all: the run succeeds with the CPU aamap, results.json says so
#   wrong-device a device named by AAMAP_DEVICE is absent: an error listing the devices, nothing written
#   geometric-no-device  snapshot.map: geometric without a device: an error (the CPU path is luminance only)
#   unwritable   the output folder cannot be created: one error line, a non-zero exit, nothing written
#   sigint       SIGINT mid-run: a message, exit 130, finished renders kept; the same command resumes
#   disk-full    the disk fills up mid-run (test hook AAMAP_TEST_WRITE_FAULT, core/atomic_file.h): one
#                error naming the file, a non-zero exit, no temporary or half-written file, finished
#                renders intact; the same command then completes
#   write-eio    an I/O error on the first file written: one error, nothing half-written
#   disk-full-tmpfs  the same on a real full disk: OUTDIR on a small tmpfs (skipped, exit 77, where
#                no mount namespace can be made)
#   device-lost  the Vulkan device is lost during the Snapshot (test hook AAMAP_TEST_VK_FAULT,
#                engine/vk/check.h): a warning, the CPU aamap, results.json records why
#   device-oom   out of device memory at the first submission: the same fallback
#   device-lost-geometric  a geometric map cannot fall back: an error
# usage: environment_checks.sh AAMAP CONFIG WORKDIR CHECK
set -u
aamap=$1 config=$2 work=$3 check=$4
rm -rf "$work" && mkdir -p "$work"
small=(--no-plots)
die() { echo "FAIL: $*"; exit 1; }

case "$check" in
no-device)
  VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json \
    "$aamap" run "$config" -o "$work/out" "${small[@]}" 2> "$work/stderr" || { cat "$work/stderr"; die "run failed"; }
  grep -q "building the aamap on the CPU" "$work/stderr" || die "no warning about the CPU fallback"
  grep -q '"vulkan_device": *"cpu-fallback' "$work/out/results.json" || die "results.json does not record the CPU path"
  [ -s "$work/out/aamap.exr" ] || die "no aamap.exr"
  ;;
wrong-device)
  AAMAP_DEVICE=no-such-device-anywhere "$aamap" run "$config" -o "$work/out" "${small[@]}" 2> "$work/stderr"
  rc=$?
  cat "$work/stderr"
  [ "$rc" -ne 0 ] || die "exit code 0"
  grep -q "aamap: error: no Vulkan device matches 'no-such-device-anywhere'" "$work/stderr" || die "no error naming the device"
  [ ! -e "$work/out" ] || die "an output folder was written"
  ;;
geometric-no-device)
  VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json \
    "$aamap" run "$config" -o "$work/out" "${small[@]}" --set snapshot.map=geometric 2> "$work/stderr"
  rc=$?
  cat "$work/stderr"
  [ "$rc" -ne 0 ] || die "exit code 0"
  grep -q "aamap: error: snapshot.map: geometric needs a Vulkan device" "$work/stderr" || die "no error naming the map"
  ;;
unwritable)
  echo "a file, not a folder" > "$work/blocker"
  "$aamap" run "$config" -o "$work/blocker/out" "${small[@]}" 2> "$work/stderr"
  rc=$?
  cat "$work/stderr"
  [ "$rc" -ne 0 ] || die "exit code 0"
  [ "$(grep -c 'aamap: error:' "$work/stderr")" -eq 1 ] || die "expected one error line"
  grep -q "blocker" "$work/stderr" || die "the error does not name the folder"
  [ "$(ls -A "$work" | sort | tr '\n' ' ')" = "blocker stderr " ] || die "something was written: $(ls -A "$work")"
  ;;
sigint)
  more=(--no-plots --set image.width=128 --set image.height=128)
  "$aamap" run "$config" -o "$work/out" "${more[@]}" 2> "$work/stderr" &
  pid=$!
  for _ in $(seq 1 600); do  # until the first render is committed (at most 60 s)
    [ -n "$(find "$work/out/cache" -name record.json 2>/dev/null | head -1)" ] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  kill -INT "$pid" 2>/dev/null
  wait "$pid"
  rc=$?
  kept=$(find "$work/out/cache" -name record.json 2>/dev/null | wc -l)
  echo "exit $rc, $kept finished render(s) kept"
  if [ "$rc" -ne 0 ]; then  # (rc 0: the run finished before the signal; nothing to check)
    [ "$rc" -eq 130 ] || { cat "$work/stderr"; die "exit $rc, expected 130"; }
    grep -q "interrupted; finished renders are kept" "$work/stderr" || die "no message"
    [ "$kept" -ge 1 ] || die "no finished render kept"
  fi
  "$aamap" run "$config" -o "$work/out" "${more[@]}" 2> "$work/stderr2" || { cat "$work/stderr2"; die "resume failed"; }
  [ -s "$work/out/results.json" ] || die "no results.json after resuming"
  ;;
disk-full|write-eio|disk-full-tmpfs)
  # A complete run first: its total output size places the fault, and its images are what every
  # image left by the failed run must equal byte for byte (outputs are deterministic).
  "$aamap" run "$config" -o "$work/ref" "${small[@]}" 2> "$work/stderr-ref" || { cat "$work/stderr-ref"; die "reference run failed"; }
  total=$(find "$work/ref" -type f -printf '%s\n' | awk '{s += $1} END {print s}')
  message="No space left on device"
  case "$check" in
  disk-full) env=(env "AAMAP_TEST_WRITE_FAULT=ENOSPC@$((total / 2))") ;;
  write-eio) env=(env AAMAP_TEST_WRITE_FAULT=EIO@100) message="Input/output error" ;;
  disk-full-tmpfs)
    # A real full disk: OUTDIR on a tmpfs of half the output's size, in a private mount
    # namespace (as root, or as a user where user namespaces are allowed); skipped elsewhere.
    ns=(unshare --mount)
    [ "$(id -u)" -eq 0 ] || ns=(unshare --user --map-root-user --mount)
    mkdir -p "$work/out"
    "${ns[@]}" mount -t tmpfs -o size=4k tmpfs "$work/out" 2>/dev/null || { echo "SKIP: cannot mount a tmpfs"; exit 77; }
  esac
  failed_run_checks() {  # the failed run's output, then the rerun
    rc=$1
    cat "$work/stderr"
    [ "$rc" -ne 0 ] || die "exit code 0"
    [ "$(grep -c 'aamap: error:' "$work/stderr")" -eq 1 ] || die "expected one error line"
    grep -q "aamap: error: $work/out/.*: cannot write: $message" "$work/stderr" || die "the error does not name the file and the cause"
    leftovers=$(find "$work/out" -name '*.tmp-*')
    [ -z "$leftovers" ] || die "temporary files left: $leftovers"
    for f in $(cd "$work/out" && find . -type f \( -name '*.exr' -o -name '*.png' \)); do
      cmp -s "$work/out/$f" "$work/ref/$f" || die "$f differs from the complete run's (half-written?)"
    done
    for d in "$work/out"/cache/*/; do
      [ -d "$d" ] || continue
      [ -s "$d/record.json" ] || die "cache entry $d without record.json"
      python3 -c 'import json, sys; json.load(open(sys.argv[1]))' "$d/record.json" || die "$d/record.json is not JSON"
    done
    echo "$(find "$work/out/cache" -name record.json 2>/dev/null | wc -l) finished render(s) kept; $total bytes in a complete run"
  }
  if [ "$check" = disk-full-tmpfs ]; then
    # The tmpfs lives only in the namespace: check inside it (the rerun would find it full again).
    export -f failed_run_checks die
    export work message total
    "${ns[@]}" bash -c 'mount -t tmpfs -o size=$((total / 2)) tmpfs "$work/out" || exit 1
      "$0" run "$1" -o "$work/out" --no-plots 2> "$work/stderr"; failed_run_checks $?' "$aamap" "$config" || exit 1
  else
    "${env[@]}" "$aamap" run "$config" -o "$work/out" "${small[@]}" 2> "$work/stderr"
    failed_run_checks $?
    "$aamap" run "$config" -o "$work/out" "${small[@]}" 2> "$work/stderr2" || { cat "$work/stderr2"; die "rerun failed"; }
    for f in $(cd "$work/ref" && find . -type f \( -name '*.exr' -o -name '*.png' \)); do
      cmp -s "$work/out/$f" "$work/ref/$f" || die "$f differs after the rerun"
    done
  fi
  ;;
device-lost|device-oom|device-lost-geometric)
  case "$check" in
    device-oom) fault=VK_ERROR_OUT_OF_DEVICE_MEMORY@0 result=VK_ERROR_OUT_OF_DEVICE_MEMORY map=luminance ;;
    device-lost) fault=VK_ERROR_DEVICE_LOST@1 result=VK_ERROR_DEVICE_LOST map=luminance ;;
    *) fault=VK_ERROR_DEVICE_LOST@1 result=VK_ERROR_DEVICE_LOST map=geometric ;;
  esac
  AAMAP_TEST_VK_FAULT=$fault "$aamap" run "$config" -o "$work/out" "${small[@]}" --set snapshot.map=$map 2> "$work/stderr"
  rc=$?
  cat "$work/stderr"
  if [ "$map" = geometric ]; then
    [ "$rc" -ne 0 ] || die "exit code 0"
    grep -q "aamap: error: snapshot.map: geometric needs a Vulkan device, and the Vulkan device .* failed during the Snapshot: $result" "$work/stderr" || die "no error naming the map and the failure"
  else
    [ "$rc" -eq 0 ] || die "run failed"
    grep -q "failed during the Snapshot: $result.*building the aamap on the CPU" "$work/stderr" || die "no warning about the failure and the CPU fallback"
    grep -q "\"vulkan_device\": *\"cpu-fallback: the Vulkan device .* failed during the Snapshot: $result\"" "$work/out/results.json" || die "results.json does not record the CPU path and why"
    [ -s "$work/out/aamap.exr" ] || die "no aamap.exr"
  fi
  ;;
*) die "unknown check $check" ;;
esac
echo "PASS: $check"
