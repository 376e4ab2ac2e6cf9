#!/usr/bin/env python3
"""`aamap run --executor ray` on Ray clusters of this machine only.

1. equal: a run through a local Ray that the executor starts and stops gives the cache entries
   (images, rays per pixel, aamap) bit for bit and the metrics of a plain local run.
2. retried: the Ray worker running the reference is killed mid-task; Ray retries it and the
   result is the reference a local process computes.
3. exhausted: the worker, then the retry's aamap process, are killed, more often than
   AAMAP_RAY_MAX_RETRIES=1 allows (both kinds of death are retried); that render is
   reported by name, the others are committed, the exit status is non-zero; the same command
   again computes only that render.
4. resumed: the driver is killed (SIGKILL) mid-run; nothing half-written is left under a final
   name, and the same command again computes only what is missing (with timing.same_machine,
   whose renders of one rpp are pinned to one node).
2-4 share one cluster that this script starts; every node of it is this machine.
Exit 77 (skipped) when the venv lacks ray.
"""
import argparse
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

CONFIG = """scene: builtin:cornell
image: {width: 32, height: 32}
threads: 1
renders:
  - {strategy: uniform, rpp: 4, series: Standard}
  - {strategy: aamap, rpp: 4, series: Selective}
reference: {type: uniform, rpp: 64}
metrics: {map_quality: false}
report: {plots: false}
"""
SLOW_REFERENCE = ["--set", "reference.rpp=1024"]  # a task long enough to be killed mid-way

failures = []
KILLED = set()  # Ray workers this script killed


def check(condition, message, detail=""):
    """detail (a command's stderr, say) is printed only when the check fails."""
    print(f"  {'ok' if condition else 'FAILED'}: {message}", flush=True)
    if not condition:
        failures.append(message)
        if detail:
            print(detail[-2000:], flush=True)
    return condition


def aamap(args, **kw):
    return subprocess.run([ARGS.aamap, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)


def work_list(out, extra=()):
    proc = aamap(["run", CONFIG_PATH, "-o", out, "-q", *extra, "--list-work"])
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def entries(cache):
    """{key: {file: bytes}} of the complete entries; asserts none is half-written."""
    result = {}
    for name in sorted(os.listdir(cache)):
        path = os.path.join(cache, name)
        if ".tmp-" in name:
            continue  # a temporary: removed by the next run, never read
        check(os.path.isfile(os.path.join(path, "record.json")), f"{name} under its final name is complete")
        result[name] = {f: open(os.path.join(path, f), "rb").read() for f in sorted(os.listdir(path))
                        if f.endswith(".exr")}
    return result


def same_images(a, b, what):
    check(sorted(a) == sorted(b), f"{what}: the same cache keys ({len(a)})")
    for key in sorted(set(a) & set(b)):
        check(a[key] == b[key], f"{what}: entry {key}: {', '.join(a[key])} bit-identical")


def wait_for_task(key, proc, timeout=60):
    """(aamap, Ray worker): the pids of a running `aamap --only KEY` and of the worker that runs it."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        for pid in os.listdir("/proc"):
            if not pid.isdigit():
                continue
            try:
                cmd = open(f"/proc/{pid}/cmdline", "rb").read().split(b"\0")
                if b"--only" in cmd and key.encode() in cmd:
                    stat = open(f"/proc/{pid}/stat").read()
                    parent = int(stat[stat.rindex(")") + 2:].split()[1])  # the Ray worker
                    # Not a child that outlived a worker killed before (its parent is then another)
                    if parent not in KILLED and b"ray" in open(f"/proc/{parent}/cmdline", "rb").read():
                        return int(pid), parent
            except (OSError, ValueError):
                continue
        time.sleep(0.005)
    return None


def kill_worker_of(key, proc):
    """Kills the Ray worker running item KEY (its aamap dies with it)."""
    found = wait_for_task(key, proc)
    if found is None:
        return False
    os.kill(found[1], signal.SIGKILL)
    KILLED.add(found[1])
    return True


def kill_aamap_of(key, proc):
    """Kills the aamap of item KEY, not its worker: as the kernel's OOM killer would."""
    found = wait_for_task(key, proc)
    if found is None:
        return False
    os.kill(found[0], signal.SIGKILL)
    KILLED.add(found[0])
    return True


def raylet_count():
    count = 0
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            count += open(f"/proc/{pid}/comm").read().strip() == "raylet"
        except OSError:
            pass
    return count


def scenario_equal():
    print("equal: a local Ray started by the executor against a plain run", flush=True)
    local, distributed = os.path.join(ARGS.work, "local"), os.path.join(ARGS.work, "equal")
    plain = aamap(["run", CONFIG_PATH, "-o", local])
    check(plain.returncode == 0, "the plain run succeeds", plain.stderr)
    items = work_list(distributed)["items"]
    check([i["kind"] for i in items] == ["snapshot"] + ["render"] * 3, "--list-work: the Snapshot first, 3 renders")
    raylets = raylet_count()
    ray_run = aamap(["run", CONFIG_PATH, "-o", distributed, "--executor", "ray"])
    check(ray_run.returncode == 0, "the Ray run succeeds", ray_run.stderr)
    check("4 of 4 item(s) computed" in ray_run.stderr, "the Ray run computed the 4 items")
    check(" 0 traced, " in ray_run.stderr, "the local run after it traced nothing")
    check(raylet_count() == raylets, "the local Ray the executor started is stopped")
    same_images(entries(os.path.join(local, "cache")), entries(os.path.join(distributed, "cache")), "equal")
    a = json.load(open(os.path.join(local, "results.json")))
    b = json.load(open(os.path.join(distributed, "results.json")))
    for ra, rb in zip(a["renders"], b["renders"]):
        check(ra["key"] == rb["key"] and ra["metrics"] == rb["metrics"], f"equal: {ra['name']}: the same metrics")
        check(rb["machine"]["hostname"] != "" and rb["machine"]["cpu_model"] != "", f"equal: {rb['name']}: machine kept")
    check(len(a["renders"]) == len(b["renders"]) == 2, "both runs report 2 renders")
    return entries(os.path.join(local, "cache"))


def reference_key(out, extra):
    return next(i["key"] for i in work_list(out, extra)["items"] if i["name"] == "reference")


def scenario_retried(address):
    print("retried: the reference's worker is killed once", flush=True)
    out = os.path.join(ARGS.work, "retried")
    key = reference_key(out, SLOW_REFERENCE)
    proc = subprocess.Popen([ARGS.aamap, "run", CONFIG_PATH, "-o", out, *SLOW_REFERENCE, "--executor", "ray",
                             "--ray-address", address], stderr=subprocess.PIPE, text=True)
    killed = kill_worker_of(key, proc)
    _, err = proc.communicate(timeout=300)
    check(killed, "a worker running the reference was killed")
    check(proc.returncode == 0, "the run succeeds after the retry", err)
    check("4 of 4 item(s) computed" in err, "every item computed")
    check_dir = os.path.join(ARGS.work, "retried_check")
    alone = aamap(["run", CONFIG_PATH, "-o", check_dir, *SLOW_REFERENCE, "--only", key])
    check(alone.returncode == 0, "the reference alone in this process", alone.stderr)
    same_images({key: entries(os.path.join(out, "cache"))[key]}, entries(os.path.join(check_dir, "cache")),
                "retried reference")
    return entries(os.path.join(out, "cache"))


def scenario_exhausted(address, retried):
    print("exhausted: the reference is killed more often than the retries allow", flush=True)
    out = os.path.join(ARGS.work, "exhausted")
    key = reference_key(out, SLOW_REFERENCE)
    command = [ARGS.aamap, "run", CONFIG_PATH, "-o", out, *SLOW_REFERENCE, "--executor", "ray", "--ray-address", address]
    proc = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, env={**os.environ, "AAMAP_RAY_MAX_RETRIES": "1"})
    kills = kill_worker_of(key, proc) + kill_aamap_of(key, proc)
    _, err = proc.communicate(timeout=300)
    check(kills == 2, "the reference's worker, then the retry's aamap were killed (1 try + 1 retry)")
    check(proc.returncode != 0, "the run exits non-zero")
    check(f"aamap: error: reference ({key})" in err, "the failed render is named")
    check("3 of 4 item(s) computed" in err, "the other items completed")
    check(sorted(entries(os.path.join(out, "cache"))) == sorted(k for k in retried if k != key),
          "every other entry is committed")
    again = subprocess.run(command, stderr=subprocess.PIPE, text=True)
    check(again.returncode == 0, "the same command again succeeds", again.stderr)
    check("1 of 1 item(s) computed" in again.stderr, "it computed only the reference")
    same_images(retried, entries(os.path.join(out, "cache")), "exhausted then rerun")


def scenario_resumed(address, retried):
    print("resumed: the driver is killed mid-run, then the same command runs again", flush=True)
    out = os.path.join(ARGS.work, "resumed")
    cache = os.path.join(out, "cache")
    # timing.same_machine pins each rpp's renders to one node (the cache keys do not depend on it)
    command = [ARGS.aamap, "run", CONFIG_PATH, "-o", out, *SLOW_REFERENCE, "--set", "timing.same_machine=true",
               "--executor", "ray", "--ray-address", address]
    check(any(i["group"] for i in work_list(out, command[5:9])["items"]), "timing.same_machine: grouped items")
    proc = subprocess.Popen(command, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:  # until the first entry is committed
        if os.path.isdir(cache) and any(os.path.isfile(os.path.join(cache, e, "record.json"))
                                        for e in os.listdir(cache) if ".tmp-" not in e):
            break
        time.sleep(0.01)
    proc.send_signal(signal.SIGKILL)  # the executor is this process: the aamap binary exec'd it
    proc.wait()
    before = entries(cache)
    check(0 < len(before) < 4, f"the killed driver had committed some items, not all ({len(before)})")
    again = subprocess.run(command, stderr=subprocess.PIPE, text=True)
    check(again.returncode == 0, "the same command again succeeds", again.stderr)
    missing = 4 - len(before)
    check(f"{missing} of {missing} item(s) computed" in again.stderr, f"it computed only the {missing} missing item(s)")
    check(not any(".tmp-" in e for e in os.listdir(cache)), "no temporaries left in the cache")
    same_images(retried, entries(cache), "resumed")


def main():
    try:
        import ray
    except ImportError:
        print(f"skipped: {sys.executable} has no ray (run tools/python-env.sh)")
        return 77
    shutil.rmtree(ARGS.work, ignore_errors=True)
    os.makedirs(ARGS.work)
    global CONFIG_PATH
    CONFIG_PATH = os.path.join(ARGS.work, "tiny.yaml")
    with open(CONFIG_PATH, "w") as f:
        f.write(CONFIG)
    start = time.monotonic()
    scenario_equal()
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        address = ray.get_runtime_context().gcs_address
        # Ray on Linux replaces 127.0.0.1 by the machine's own interface address: check that
        # every node is this machine (an address a socket here can bind to).
        for node in ray.nodes():
            with socket.socket() as probe:
                try:
                    probe.bind((node["NodeManagerAddress"], 0))
                    local = True
                except OSError:
                    local = False
            check(local, f"the cluster's node {node['NodeManagerAddress']} is this machine")
        retried = scenario_retried(address)
        scenario_exhausted(address, retried)
        scenario_resumed(address, retried)
    finally:
        ray.shutdown()
    print(f"{len(failures)} check(s) failed; {time.monotonic() - start:.1f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--aamap", required=True)
    parser.add_argument("--work", required=True)
    ARGS = parser.parse_args()
    sys.exit(main())
