"""Runner of the peer benchmark: rbsim against ODE, Bullet and MuJoCo.

    run.py --build DIR [--quick] [--results DIR] [--budget SECONDS]
           [--engines rbsim,ode,bullet,mujoco] [--skip-scaling]

Called by run.sh (which builds DIR first).  Every run is a separate process
(its peak memory is getrusage's ru_maxrss, taken by peers_spawn); engines alternate run
by run within each scene (A B C D, then D C B A, ...) so that every ratio
compares runs made at nearly the same time, and the tables give medians.
A run that reaches its wall-time cap stops early and says how far it got;
one that does not end within its hard limit is killed and counted as such.
Writes RESULTS/peers.csv (every run), RESULTS/peers.md (tables),
RESULTS/peers.png and RESULTS/scaling.png.
"""
import argparse
import csv
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import scenes  # noqa: E402

ENGINES = ["rbsim", "ode", "bullet", "mujoco"]

# Bytes rbsim must move per body-step at the least (its state layout, see
# peers.md): position 3, velocity 3, angular velocity 3 and orientation 4
# doubles read and written once (2 x 104 B), plus radius, inverse mass and
# inverse inertia read (24 B).  Each contact slot (size measured from
# rbs_world_memory_size) is written once when found and read once by the
# solver.  A lower bound: the rollback saves, broad phase and extra solver
# sweeps only add to it.
STATE_BYTES = 2 * 13 * 8 + 3 * 8
# Arithmetic per body-step at the least (double-precision operations):
# integrating velocity and position and the quaternion update ~60, one swept
# overlap test per neighbour pair ~30, one contact solve ~120 (normal +
# friction impulse, both bodies).  Rough; stated as such.
STATE_FLOPS = 60
PAIR_FLOPS = 30
CONTACT_FLOPS = 120


def now():
    return time.monotonic()


def plan(quick):
    """The configurations: (scene, n, steps, {engine: (repeats, cap s)}).
    The cap is the wall time after which a run stops stepping."""
    if quick:
        return [
            ("ball", 1, 2000, {e: (1, 30) for e in ENGINES}),
            ("billiards", 16, 2000, {e: (1, 30) for e in ENGINES}),
            ("pile", 1000, 500, {e: (1, 60) for e in ENGINES}),
        ]
    return [
        ("ball", 1, 2000, {e: (5, 30) for e in ENGINES}),
        ("billiards", 16, 2000, {e: (5, 30) for e in ENGINES}),
        ("pile", 1000, 2000, {"rbsim": (5, 60), "ode": (5, 60), "bullet": (3, 90), "mujoco": (3, 60)}),
        ("pile", 8000, 2000, {"rbsim": (3, 120), "ode": (3, 150), "bullet": (1, 420), "mujoco": (2, 200)}),
        ("pile", 27000, 100, {"rbsim": (3, 120), "ode": (2, 120), "bullet": (1, 240), "mujoco": (1, 200)}),
    ]


def scaling_plan(quick):
    ns = [1000, 10000] if quick else [1000, 3000, 10000, 30000, 100000, 300000, 1000000]
    return [(kind, n) for kind in ("lattice", "stack") for n in ns]


def driver_cmd(build, engine, scene_path, steps, cap, state_path):
    if engine in ("rbsim", "ode"):
        cmd = [os.path.join(build, "bench", "peers", f"peers_{engine}")]
    else:
        cmd = [sys.executable, os.path.join(HERE, f"drive_{engine}.py")]
    return cmd + ["--scene", scene_path, "--steps", str(steps), "--max-wall", str(cap),
                  "--state-out", state_path]


def run_process(build, cmd, hard_limit, log_path):
    """Run cmd through peers_spawn (stdout and stderr to log_path); returns
    (exit code or None if killed, peak RSS kB, wall s, output text)."""
    spawn = os.path.join(build, "bench", "peers", "peers_spawn")
    env = dict(os.environ, PYTHONPATH=HERE + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r = subprocess.run([spawn, str(hard_limit), log_path] + cmd, capture_output=True, text=True,
                       env=env, timeout=hard_limit + 60)
    if r.returncode != 0:
        raise RuntimeError(f"peers_spawn failed: {r.stderr.strip()}")
    info = json.loads(r.stdout)
    with open(log_path) as fh:
        text = fh.read()
    return (None if info["killed"] else info["exit"]), info["maxrss_kb"], info["wall"], text


def parse_driver(text):
    result, progress = None, None
    for line in text.splitlines():
        if line.startswith("RESULT "):
            result = json.loads(line[7:])
        elif line.startswith("# progress "):
            _, _, k, w = line.split()
            progress = (int(k), float(w))
    return result, progress


def quality(build, scene_path, state_path):
    exe = os.path.join(build, "bench", "peers", "peers_quality")
    r = subprocess.run([exe, scene_path, state_path], capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        return {"quality_error": r.stderr.strip()}
    return json.loads(r.stdout)


def one_run(build, work, engine, scene, n, steps, cap, rep):
    scene_path = os.path.join(work, f"{scene}_{n}.bin")
    state_path = os.path.join(work, f"{scene}_{n}.{engine}.state")
    log_path = os.path.join(work, f"{scene}_{n}.{engine}.{rep}.log")
    if os.path.exists(state_path):
        os.remove(state_path)
    hard = cap * 1.5 + 120
    code, rss, elapsed, text = run_process(
        build, driver_cmd(build, engine, scene_path, steps, cap, state_path), hard, log_path)
    res, progress = parse_driver(text)
    row = {"scene": scene, "n": n, "engine": engine, "rep": rep, "steps_planned": steps,
           "cap_s": cap, "maxrss_kb": rss, "process_s": round(elapsed, 3)}
    if res is None:
        row["status"] = "killed" if code is None else f"failed (exit {code})"
        tail = [l for l in text.splitlines() if not l.startswith("# progress")][-3:]
        row["error"] = " | ".join(tail)[:300]
        if progress:
            row["steps"], row["wall"] = progress
            row["sim_time"] = progress[0] * scenes.DT
    else:
        for k in ("steps", "sim_time", "wall", "setup_wall", "version"):
            row[k] = res.get(k)
        row["apex"] = ";".join(f"{z:.6f}" for z in res.get("apex", [])[:6])
        extra = {k: v for k, v in res.items()
                 if k not in ("engine", "n", "steps", "sim_time", "wall", "setup_wall", "apex",
                              "error", "version", "dt")}
        row["extra"] = json.dumps(extra, sort_keys=True)
        row["error"] = res.get("error", "")
        if row["error"]:
            row["status"] = "error"
        elif res["steps"] < steps:
            row["status"] = "capped"
        else:
            row["status"] = "ok"
        if os.path.exists(state_path):
            row.update(quality(build, scene_path, state_path))
            os.remove(state_path)
    if row.get("steps") and row.get("wall"):
        row["wall_per_sim_s"] = row["wall"] / row["sim_time"]
        row["body_steps_per_s"] = n * row["steps"] / row["wall"]
        row["ns_per_body_step"] = 1e9 * row["wall"] / (n * row["steps"])
    return row


def log(msg):
    print(msg, flush=True)


def machine_info(build):
    info = {}
    try:
        with open("/proc/cpuinfo") as f:
            lines = f.read().splitlines()
        def first(key):
            for l in lines:
                if l.startswith(key):
                    return l.split(":", 1)[1].strip()
            return "?"
        info["cpu"] = first("model name")
        info["mhz"] = first("cpu MHz")
        info["cache"] = first("cache size")
        flags = first("flags").split()
        info["simd"] = " ".join(f for f in ("sse4_2", "avx", "avx2", "fma", "avx512f") if f in flags)
    except OSError:
        info["cpu"] = "?"
    info["nproc"] = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    try:
        with open("/proc/meminfo") as f:
            info["memory"] = f.readline().split(":", 1)[1].strip()
    except OSError:
        info["memory"] = "?"
    info["kernel"] = platform.release()
    info["python"] = platform.python_version()
    cc = subprocess.run(["cc", "--version"], capture_output=True, text=True).stdout.splitlines()
    info["cc"] = cc[0] if cc else "?"
    vers = {}
    try:
        from importlib import metadata
        for pkg in ("pybullet", "mujoco", "numpy", "matplotlib"):
            try:
                vers[pkg] = metadata.version(pkg)
            except metadata.PackageNotFoundError:
                vers[pkg] = "missing"
    except ImportError:
        pass
    ode = subprocess.run(["pkg-config", "--modversion", "ode"], capture_output=True, text=True)
    vers["ode"] = ode.stdout.strip() or "missing"
    info["versions"] = vers
    return info


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", required=True, help="meson build directory with bench/peers built")
    ap.add_argument("--results", default=os.path.join(HERE, "..", "results"))
    ap.add_argument("--quick", action="store_true", help="N = 1000 only, 0.5 s, one repeat")
    ap.add_argument("--budget", type=float, default=38 * 60,
                    help="seconds; later repeats are skipped when they would overrun it")
    ap.add_argument("--engines", default=",".join(ENGINES))
    ap.add_argument("--skip-scaling", action="store_true")
    ap.add_argument("--skip-peers", action="store_true")
    a = ap.parse_args(argv)
    engines = [e for e in a.engines.split(",") if e]
    for e in engines:
        if e not in ENGINES:
            ap.error(f"unknown engine {e!r}; known: {', '.join(ENGINES)}")
    build = os.path.abspath(a.build)
    results = os.path.abspath(a.results)
    exe = os.path.join(build, "bench", "peers", "peers_rbsim")
    if not os.path.exists(exe):
        sys.exit(f"run.py: {exe} is missing: build first (bench/peers/run.sh does)")
    if "ode" in engines and not os.path.exists(os.path.join(build, "bench", "peers", "peers_ode")):
        log("run.py: peers_ode was not built (no libode-dev): ODE is left out")
        engines.remove("ode")
    for e, mod in (("bullet", "pybullet"), ("mujoco", "mujoco")):
        if e in engines:
            try:
                __import__(mod)
            except ImportError:
                log(f"run.py: Python module {mod} is missing: {e} is left out")
                engines.remove(e)
    work = os.path.join(build, "bench-peers-work")
    os.makedirs(work, exist_ok=True)
    os.makedirs(results, exist_ok=True)
    t_start = now()
    rows = []

    info = machine_info(build)
    log(f"machine: {info['cpu']}, {info['nproc']} cores, {info['memory']}")
    r = subprocess.run([os.path.join(build, "bench", "peers", "peers_stream")],
                       capture_output=True, text=True, timeout=600)
    stream = json.loads(r.stdout)
    log(f"stream: copy {stream['copy_gbs']} GB/s, triad {stream['triad_gbs']} GB/s, "
        f"{stream['gflops_scalar']} GFLOP/s")
    layout = json.loads(subprocess.run([exe, "--layout"], capture_output=True, text=True).stdout)

    # Peer comparison: per configuration, repeats interleaved across engines.
    expected = {}
    if not a.skip_peers:
        for scene, n, steps, reps in plan(a.quick):
            scenes.write(os.path.join(work, f"{scene}_{n}.bin"), scene, n)
            todo = [e for e in engines if e in reps]
            maxrep = max(reps[e][0] for e in todo)
            for rep in range(maxrep):
                order = todo if rep % 2 == 0 else todo[::-1]
                for e in order:
                    nrep, cap = reps[e]
                    if rep >= nrep:
                        continue
                    key = (scene, n, e)
                    if rep > 0:
                        prev = [x for x in rows if (x["scene"], x["n"], x["engine"]) == key]
                        if any(x["status"] != "ok" for x in prev):
                            continue  # capped or failed once: one run says it
                        left = a.budget - (now() - t_start)
                        if expected.get(key, 0) > left:
                            log(f"  skip {scene} {n} {e} rep {rep + 1}: budget")
                            continue
                    row = one_run(build, work, e, scene, n, steps, cap, rep + 1)
                    expected[key] = row["process_s"]
                    rows.append(row)
                    log(f"{scene:9s} n={n:6d} {e:6s} rep {rep + 1}: {row['status']:8s} "
                        f"sim {row.get('sim_time', 0) or 0:.3f} s in {row.get('wall', 0) or 0:.2f} s, "
                        f"{row['maxrss_kb'] / 1024:.0f} MB, escaped {row.get('escaped', '-')}, "
                        f"ss {row.get('max_ss_overlap_rel', '-')}, sp {row.get('max_sp_overlap_rel', '-')}"
                        f"   [{now() - t_start:.0f} s]")

    # rbsim alone, 1e3 .. 1e6 spheres.
    if not a.skip_scaling:
        stop = set()
        for kind, n in scaling_plan(a.quick):
            if kind in stop:
                continue
            left = a.budget - (now() - t_start)
            if left < 60:
                log(f"  skip scaling {kind} {n}: budget")
                continue
            scenes.write(os.path.join(work, f"{kind}_{n}.bin"), kind, n)
            cap = min(60.0, max(10.0, left / 4))
            row = one_run(build, work, "rbsim", kind, n, 20, cap, 1)
            os.remove(os.path.join(work, f"{kind}_{n}.bin"))
            rows.append(row)
            log(f"scaling {kind:7s} n={n:7d}: {row['status']} {row.get('steps', 0)} steps, "
                f"{row.get('ns_per_body_step', float('nan')):.0f} ns/body-step, "
                f"{row['maxrss_kb'] / 1024:.0f} MB   [{now() - t_start:.0f} s]")
            if row["status"] != "ok":
                stop.add(kind)

    total = now() - t_start
    log(f"total {total:.0f} s")
    write_csv(os.path.join(results, "peers.csv"), rows)
    git = subprocess.run(["git", "-C", HERE, "describe", "--always", "--dirty"],
                         capture_output=True, text=True).stdout.strip()
    meta = {"machine": info, "stream": stream, "layout": layout, "quick": a.quick,
            "total_s": total, "engines": engines, "commit": git or "?",
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    with open(os.path.join(results, "peers_meta.json"), "w") as f:
        json.dump(meta, f, indent=1, sort_keys=True)
    import report
    report.write(results, meta)
    return 0


CSV_FIELDS = ["scene", "n", "engine", "rep", "status", "steps_planned", "steps", "sim_time",
              "wall", "setup_wall", "process_s", "cap_s", "wall_per_sim_s", "body_steps_per_s",
              "ns_per_body_step", "maxrss_kb", "escaped", "nonfinite", "max_ss_overlap_rel",
              "max_sp_overlap_rel", "ss_over_1pct", "sp_over_1pct", "kinetic", "potential",
              "energy", "apex", "version", "error", "extra"]


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in CSV_FIELDS})


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
