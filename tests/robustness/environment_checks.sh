#!/usr/bin/env bash
# Failures of the environment, through the `aamap` command (issue 9):
#   no-device    no Vulkan driver at all: the run succeeds with the CPU aamap, results.json says so
#   wrong-device a device named by AAMAP_DEVICE is absent: an error listing the devices, nothing written
#   geometric-no-device  snapshot.map: geometric without a device: an error (the CPU path is luminance only)
#   unwritable   the output folder cannot be created: one error line, a non-zero exit, nothing written
#   sigint       SIGINT mid-run: a message, exit 130, finished renders kept; the same command resumes
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
*) die "unknown check $check" ;;
esac
echo "PASS: $check"
