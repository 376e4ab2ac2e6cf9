#!/usr/bin/env python3
"""`aamap run CONFIG --executor ray`: the experiment's missing Snapshots and renders as Ray tasks.

The aamap binary execs this script with the venv's Python. It asks the binary for the work the
cache lacks (`aamap run ... --list-work`), runs each item as a Ray task that calls the binary on a
worker (`aamap run ... --only KEY --cache TMP`) and returns the finished cache entry as tar bytes,
commits every entry atomically into OUTDIR/cache (a temporary folder renamed into place, as the
binary does), then replaces itself with the plain local run, which finds everything cached and
computes metrics and the report.

Files reach the workers through shared paths: every worker must see the binary, the config and
the scenes at the same absolute paths as the driver (one machine, NFS, a Slurm cluster's shared
file system, a volume mounted into every KubeRay pod). Only cache entries travel through Ray.

Environment: AAMAP_RAY_MAX_RETRIES (default 3): how often a task whose worker died is retried.
Exit status: the binary's own for a bad config; 1 when some item failed (each named on stderr;
the others are committed and a rerun of the same command computes only what is missing).
"""
import argparse
import io
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tarfile
import time

EXIT_ENVIRONMENT = 1


def log(message):
    print(f"ray-executor: {message}", file=sys.stderr, flush=True)


def fail(message, code=EXIT_ENVIRONMENT):
    print(f"aamap: error: {message}", file=sys.stderr, flush=True)
    sys.exit(code)


def list_work(binary, command):
    """The binary's --list-work JSON for this command; exits with its status when it fails."""
    proc = subprocess.run([binary, *command, "--list-work"], stdout=subprocess.PIPE)
    if proc.returncode != 0:
        sys.exit(proc.returncode)  # the binary has said what is wrong
    return json.loads(proc.stdout)


def pack(folder):
    """A cache entry's files as uncompressed tar bytes (the EXRs are compressed already)."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as tar:
        for name in sorted(os.listdir(folder)):
            tar.add(os.path.join(folder, name), arcname=name, recursive=False)
    return buffer.getvalue()


def unpack(data, folder):
    """Writes pack()'s files into folder; anything but a plain file without a path is refused."""
    os.makedirs(folder, exist_ok=True)
    with tarfile.open(fileobj=io.BytesIO(data), mode="r") as tar:
        for member in tar.getmembers():
            if not member.isfile() or "/" in member.name or member.name in ("", ".", ".."):
                raise ValueError(f"unexpected member {member.name!r} in a cache entry")
            with tar.extractfile(member) as src, open(os.path.join(folder, member.name), "wb") as dst:
                shutil.copyfileobj(src, dst)


_commits = 0


def commit(cache_dir, key, data):
    """The entry under cache_dir/KEY, all or nothing: filled under KEY.tmp-PID-N (which the binary
    removes if this process dies), checked for record.json, then renamed into place."""
    global _commits
    _commits += 1
    final = os.path.join(cache_dir, key)
    tmp = os.path.join(cache_dir, f"{key}.tmp-{os.getpid()}-{_commits}")
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        unpack(data, tmp)
        if not os.path.isfile(os.path.join(tmp, "record.json")):
            raise ValueError("cache entry without record.json")
        if os.path.isdir(final):  # a stale, incomplete entry (a complete one is never recomputed)
            shutil.rmtree(final)
        os.rename(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def die_with_parent():
    """In the worker's aamap child: killed with the Ray worker, so a killed task stops at once."""
    import ctypes

    PR_SET_PDEATHSIG = 1
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)


class AamapKilled(Exception):
    """The worker's aamap died of a signal (the kernel's OOM killer, say): retried like a dead worker."""


def compute(item, binary, snapshot_entry):
    """One item on a worker: {"ok", "host", "cpu", "seconds", "entry" | "error"}. A failure of the
    binary is returned, not raised: it would fail again on any worker, so Ray must not retry it
    (Ray retries the task when its worker dies, or its aamap is killed: AamapKilled)."""
    import tempfile

    host = socket.gethostname()
    where = f"worker {host}"
    if not os.access(binary, os.X_OK):
        return {"ok": False, "host": host,
                "error": f"{where}: the aamap binary {binary} is not there (every worker needs the binary, "
                         f"the config and the scenes at the driver's paths)"}
    config = item["args"][1]
    if not os.path.isfile(config):
        return {"ok": False, "host": host,
                "error": f"{where}: the config {config} is not there (every worker needs the binary, "
                         f"the config and the scenes at the driver's paths)"}
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="aamap-ray-") as tmp:
        cache = os.path.join(tmp, "cache")
        os.makedirs(cache)
        if snapshot_entry is not None:
            if not snapshot_entry.get("ok"):
                return {"ok": False, "host": host, "error": "its Snapshot failed"}
            unpack(snapshot_entry["entry"], os.path.join(cache, item["needs_snapshot"]))
        proc = subprocess.run([binary, *item["args"], "--cache", cache], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, preexec_fn=die_with_parent)
        if proc.returncode < 0:
            raise AamapKilled(f"{where}: aamap was killed by signal {-proc.returncode}")
        if proc.returncode != 0:
            lines = [l for l in proc.stderr.splitlines() if l.strip()]
            errors = [l for l in lines if l.startswith("aamap: error:")] or lines[-3:]
            return {"ok": False, "host": host,
                    "error": f"{where}: aamap exited with status {proc.returncode}: {' / '.join(errors)}"}
        entry = os.path.join(cache, item["key"])
        if not os.path.isfile(os.path.join(entry, "record.json")):
            return {"ok": False, "host": host, "error": f"{where}: aamap wrote no cache entry {item['key']}"}
        return {"ok": True, "host": host, "seconds": time.monotonic() - start, "entry": pack(entry)}


class GroupPlacer:
    """timing.same_machine: every item of a group on one node, the groups dealt round-robin over
    the alive nodes that have the CPUs."""

    def __init__(self, ray):
        self.nodes = [n for n in ray.nodes() if n.get("Alive")]
        self.chosen = {}
        self.next = 0

    def node_for(self, group, cpus):
        if group not in self.chosen:
            fit = [n for n in self.nodes if n.get("Resources", {}).get("CPU", 0) >= cpus] or self.nodes
            self.chosen[group] = fit[self.next % len(fit)]["NodeID"]
            self.next += 1
        return self.chosen[group]


def run_on_ray(ray, binary, work, max_retries):
    """Submits every item, commits each result as it arrives; returns the failures' messages."""
    from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

    resources = ray.cluster_resources()
    has_gpu = resources.get("GPU", 0) >= 1
    largest = max([n.get("Resources", {}).get("CPU", 1) for n in ray.nodes() if n.get("Alive")] or [1])
    log(f"cluster: {len(ray.nodes())} node(s), {resources.get('CPU', 0):g} CPUs, "
        f"{resources.get('GPU', 0):g} GPUs; {len(work['items'])} item(s) to compute")
    task = ray.remote(compute)
    placer = GroupPlacer(ray)
    cache_dir = work["cache"]
    pending = {}
    submitted = {}
    cached_snapshots = {}
    for item in work["items"]:
        options = {"name": f"aamap:{item['name']}", "max_retries": max_retries, "retry_exceptions": [AamapKilled]}
        if item["kind"] == "snapshot":
            # The Snapshot is a Vulkan render: on a GPU when the cluster has one, else lavapipe.
            options.update(num_cpus=1, num_gpus=1 if has_gpu else 0)
        else:
            cpus = item["threads"] if item["threads"] > 0 else largest  # threads 0: a whole worker
            options.update(num_cpus=min(cpus, largest))
        if item["group"]:
            node = placer.node_for(item["group"], options["num_cpus"])
            options["scheduling_strategy"] = NodeAffinitySchedulingStrategy(node_id=node, soft=False)
        snapshot = None
        if item["needs_snapshot"]:
            key = item["needs_snapshot"]
            if key in submitted:
                snapshot = submitted[key]  # Ray starts the render once the Snapshot is done
            else:
                if key not in cached_snapshots:
                    entry = os.path.join(cache_dir, key)
                    cached_snapshots[key] = ray.put({"ok": True, "entry": pack(entry)})
                snapshot = cached_snapshots[key]
        ref = task.options(**options).remote(item, binary, snapshot)
        submitted[item["key"]] = ref
        pending[ref] = item

    failures = []
    done_count = 0
    total = len(pending)
    while pending:
        ready, _ = ray.wait(list(pending), num_returns=1)
        for ref in ready:
            item = pending.pop(ref)
            done_count += 1
            label = f"[{done_count}/{total}] {item['kind']} {item['name']} ({item['key']})"
            try:
                out = ray.get(ref)
            except Exception as e:  # the worker died more often than max_retries, or a dependency did
                cause = getattr(e, "cause", None) or e  # a RayTaskError wraps what the task raised
                message = str(cause).strip().splitlines()
                failures.append(f"{item['name']} ({item['key']}): {type(cause).__name__}: "
                                f"{message[0] if message else ''}")
                log(f"{label}: failed: {failures[-1]}")
                continue
            if not out["ok"]:
                failures.append(f"{item['name']} ({item['key']}): {out['error']}")
                log(f"{label}: failed: {out['error']}")
                continue
            commit(cache_dir, item["key"], out["entry"])
            log(f"{label}: done on {out['host']} in {out['seconds']:.1f} s, committed")
    return failures


def check_reachable(address):
    """A HOST:PORT that accepts no connection fails at once (Ray itself would wait on it forever)."""
    host, sep, port = address.rpartition(":")
    if not sep or "://" in address or not port.isdigit():
        return  # "auto", ray://...: Ray's own business
    try:
        socket.create_connection((host, int(port)), timeout=10).close()
    except OSError as e:
        fail(f"--ray-address {address}: no Ray cluster answers there ({e}); start one with "
             f"`ray start --head --port={port}` or leave --ray-address out for a local one")


def distribute(ray, args, command, work, max_retries):
    """Every item of work on the cluster, committed; exits non-zero when some failed."""
    start = time.monotonic()
    if args.address:
        check_reachable(args.address)
    try:
        if args.address:
            ray.init(address=args.address, log_to_driver=False)
        else:  # a cluster of this machine only, for this run
            ray.init(include_dashboard=False, log_to_driver=False)
    except Exception as e:  # Ray raises ConnectionError, ValueError, RuntimeError, ... here
        where = f"the Ray cluster at {args.address}" if args.address else "a local Ray"
        fail(f"--executor ray: cannot start or join {where}: {type(e).__name__}: {e}")
    signal.signal(signal.SIGTERM, signal.default_int_handler)  # ray.init installs its own
    log(f"connected to Ray in {time.monotonic() - start:.1f} s")
    try:
        failures = run_on_ray(ray, args.binary, work, max_retries)
    finally:
        ray.shutdown()
    log(f"{len(work['items']) - len(failures)} of {len(work['items'])} item(s) computed in "
        f"{time.monotonic() - start:.1f} s")
    if failures:
        for f in failures:
            print(f"aamap: error: {f}", file=sys.stderr)
        fail(f"{len(failures)} item(s) failed; the others are in {work['cache']}; run the same command "
             f"again to compute only what is missing")
    left = list_work(args.binary, command)["items"]
    if left:
        fail(f"still missing after the Ray run: {', '.join(i['name'] for i in left)}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", required=True, help="the aamap binary (the same path on every worker)")
    parser.add_argument("--address", help="the Ray cluster to join; default: start a local one for this run")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- and the aamap command line")
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    try:
        max_retries = int(os.environ.get("AAMAP_RAY_MAX_RETRIES", "3"))
    except ValueError:
        fail(f"AAMAP_RAY_MAX_RETRIES={os.environ['AAMAP_RAY_MAX_RETRIES']!r} is not a whole number", 2)
    try:
        import ray
    except ImportError:
        fail(f"--executor ray needs the 'ray' package in {sys.executable}; run tools/python-env.sh")

    # SIGTERM as SIGINT: the finally below stops a local cluster; committed entries stay.
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    work = list_work(args.binary, command)
    if work["items"]:
        try:
            distribute(ray, args, command, work, max_retries)
        except KeyboardInterrupt:
            print(f"\naamap: interrupted; finished renders are kept in {work['cache']}; run the same command "
                  f"again to resume", file=sys.stderr)
            sys.exit(130)
    else:
        log("every Snapshot and render is cached already")
    sys.stdout.flush()
    sys.stderr.flush()
    os.execv(args.binary, [args.binary, *command])  # metrics and the report, from the cache


if __name__ == "__main__":
    main()
