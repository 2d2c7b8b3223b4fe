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

# "ode_sap" is ODE with dSweepAndPruneSpace instead of dHashSpace: the issue
# names the hash space, but sweep-and-prune is faster here, so it is run too
# (N <= 8000) to keep the comparison fair to ODE.
# "rbsim_sel" is rbsim with RBS_METHOD_SELECTIVE (only overlapping groups roll
# back) instead of the default method.
# "rbsim" is rbsim's default method, RBS_METHOD_AUTO: the soft step from 64
# moving spheres on (every pile here), Euler with global rollback below (the
# ball, the billiards break).
# "rbsim_tol" is rbsim's Euler method with a looser impact tolerance: slop
# TOL_SLOP (0.5 % of the radius, half the 1 % overlap bound) instead of
# the library's 1e-6, so an impact shallower than that is kept where the step
# finds it instead of being rolled back to the moment of touch.
# "rbsim_soft" is rbsim with RBS_METHOD_SOFT (the soft step: fixed sub-steps
# with soft contacts, default soft_substeps = 3), the pile method.
# "rbsim_mt" is rbsim's default method stepping on two threads (--threads 2:
# a pool of one thread lent with rbs_world_set_workers), the same bits as
# "rbsim"; this machine has two cores.
ENGINES = ["rbsim", "rbsim_mt", "rbsim_sel", "rbsim_tol", "rbsim_soft", "ode", "ode_sap", "bullet", "mujoco"]
RBSIM = ("rbsim", "rbsim_mt", "rbsim_sel", "rbsim_tol", "rbsim_soft")
SCALED = ("rbsim", "rbsim_sel", "rbsim_soft")  # the 10^3 .. 10^6 series
TOL_SLOP = 0.005

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
            ("ball", 1, 2000, {e: (1, 30) for e in ENGINES if e != "ode_sap"}),
            ("billiards", 16, 2000, {e: (1, 30) for e in ENGINES if e != "ode_sap"}),
            ("pile", 1000, 500, {e: (1, 30) for e in ENGINES}),
        ]
    return [
        ("ball", 1, 2000, {e: (5, 30) for e in ENGINES if e != "ode_sap"}),
        ("billiards", 16, 2000, {e: (5, 30) for e in ENGINES if e != "ode_sap"}),
        # the small pile: the baseline of the marginal memory per body (report.py)
        ("pile", 125, 2000, {"rbsim": (3, 60), "rbsim_mt": (3, 60), "rbsim_sel": (3, 60), "rbsim_tol": (3, 60), "rbsim_soft": (3, 60),
                             "ode": (3, 60), "ode_sap": (1, 60), "bullet": (1, 60), "mujoco": (1, 60)}),
        ("pile", 1000, 2000, {"rbsim": (5, 60), "rbsim_mt": (5, 60), "rbsim_sel": (5, 60), "rbsim_tol": (5, 60), "rbsim_soft": (5, 60),
                              "ode": (5, 60),
                              "ode_sap": (3, 60), "bullet": (2, 90), "mujoco": (3, 60)}),
        ("pile", 8000, 2000, {"rbsim": (3, 90), "rbsim_mt": (3, 90), "rbsim_sel": (3, 90), "rbsim_tol": (2, 150), "rbsim_soft": (3, 90),
                              "ode": (2, 400),
                              "ode_sap": (1, 150), "bullet": (1, 200), "mujoco": (1, 150)}),
        ("pile", 27000, 100, {"rbsim": (3, 60), "rbsim_mt": (3, 60), "rbsim_sel": (3, 60), "rbsim_tol": (3, 60), "rbsim_soft": (3, 60),
                              "ode": (1, 100),
                              "bullet": (1, 60), "mujoco": (1, 60)}),
    ]


# Extra seconds a run may take to set up before stepping (the wall-time cap
# counts stepping only): MuJoCo's model compiler takes time growing as N^2
# (about 3 s at N = 4000 and 150 s of CPU at N = 27,000 on this machine).
SETUP_ALLOW = {("mujoco", 8000): 60, ("mujoco", 27000): 300}


# Runs of each scaling configuration: a single run of a few tenths of a
# second on this shared machine can be 1.5-2x off (the run at 05c09bb: the
# lattice of 3,000 at 149 ns a body-step, 75 ns in three runs after), so the
# report takes the median of three -- of seven up to 30,000 spheres, whose
# runs take a few tenths of a second (the run at 054f433: three runs of the
# 1,000 lattice at 76, 112 and 117 ns, the median 1.5x the 3,000's).
SCALING_REPS = 3
SCALING_REPS_SMALL = 7


def scaling_reps(n):
    """Runs of a scaling configuration of n spheres."""
    return SCALING_REPS_SMALL if n <= 30000 else SCALING_REPS


def scaling_steps(n):
    """Steps of a scaling run of n spheres: 2e6 / n, from 20 to 200, so that
    the small sizes step for a few tenths of a second (20 steps of 1,000
    spheres take 2 ms, of which the first step's one-off work -- the
    candidate list's first build, the first touch of the world's pages -- is
    a large and varying part: +-30 % between runs) and the large ones keep
    20 (the lattice touches the floor after 300)."""
    return max(20, min(200, int(2e6 // n)))


def scaling_plan(quick):
    ns = [1000, 10000] if quick else [1000, 3000, 10000, 30000, 100000, 300000, 1000000]
    # small sizes of every series first, so a short budget still covers them
    return [(engine, kind, n) for n in ns for engine in SCALED for kind in ("lattice", "stack")]


def driver_cmd(build, engine, scene_path, steps, cap, state_path):
    if engine in ("rbsim", "ode"):
        cmd = [os.path.join(build, "bench", "peers", f"peers_{engine}")]
    elif engine == "rbsim_mt":
        cmd = [os.path.join(build, "bench", "peers", "peers_rbsim"), "--threads", "2"]
    elif engine == "rbsim_sel":
        cmd = [os.path.join(build, "bench", "peers", "peers_rbsim"), "--method", "selective"]
    elif engine == "rbsim_tol":
        cmd = [os.path.join(build, "bench", "peers", "peers_rbsim"), "--method", "euler", "--slop", str(TOL_SLOP)]
    elif engine == "rbsim_soft":
        cmd = [os.path.join(build, "bench", "peers", "peers_rbsim"), "--method", "soft"]
    elif engine == "ode_sap":
        cmd = [os.path.join(build, "bench", "peers", "peers_ode"), "--method", "sap"]
    else:
        cmd = [sys.executable, os.path.join(HERE, f"drive_{engine}.py")]
    return cmd + ["--scene", scene_path, "--steps", str(steps), "--max-wall", str(cap),
                  "--state-out", state_path]


def run_process(build, cmd, hard_limit, log_path):
    """Run cmd through peers_spawn (stdout and stderr to log_path); returns
    (exit code or None if killed, peak RSS kB, wall s, output text, 1 if the
    process ran with address-space randomisation on)."""
    spawn = os.path.join(build, "bench", "peers", "peers_spawn")
    env = dict(os.environ, PYTHONPATH=HERE + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r = subprocess.run([spawn, str(hard_limit), log_path] + cmd, capture_output=True, text=True,
                       env=env, timeout=hard_limit + 60)
    if r.returncode != 0:
        raise RuntimeError(f"peers_spawn failed: {r.stderr.strip()}")
    info = json.loads(r.stdout)
    with open(log_path) as fh:
        text = fh.read()
    return (None if info["killed"] else info["exit"]), info["maxrss_kb"], info["wall"], text, info.get("aslr", 1)


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
    hard = cap * 1.5 + 120 + SETUP_ALLOW.get((engine, n), 0)
    code, rss, elapsed, text, aslr = run_process(
        build, driver_cmd(build, engine, scene_path, steps, cap, state_path), hard, log_path)
    res, progress = parse_driver(text)
    row = {"scene": scene, "n": n, "engine": engine, "rep": rep, "steps_planned": steps,
           "cap_s": cap, "maxrss_kb": rss, "process_s": round(elapsed, 3)}
    if res is None:
        row["status"] = "killed" if code is None else f"failed (exit {code})"
        tail = [l for l in text.splitlines() if not l.startswith("# progress")][-3:]
        row["error"] = " | ".join(tail)[:300]
        row["extra"] = json.dumps({"aslr": aslr})
        if progress:
            row["steps"], row["wall"] = progress
            row["sim_time"] = progress[0] * scenes.DT
    else:
        for k in ("steps", "sim_time", "wall", "setup_wall", "version", "rss_anon_kb"):
            row[k] = res.get(k)
        row["apex"] = ";".join(f"{z:.6f}" for z in res.get("apex", [])[:6])
        extra = {k: v for k, v in res.items()
                 if k not in ("engine", "n", "steps", "sim_time", "wall", "setup_wall", "apex",
                              "error", "version", "dt", "rss_anon_kb")}
        extra["aslr"] = aslr
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


def run_stream(build):
    r = subprocess.run([os.path.join(build, "bench", "peers", "peers_stream")],
                       capture_output=True, text=True, timeout=600)
    st = json.loads(r.stdout)
    log(f"stream: copy {st['copy_gbs']} GB/s, triad {st['triad_gbs']} GB/s, "
        f"{st['gflops_scalar']} GFLOP/s")
    return st


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
    ap.add_argument("--only", metavar="SCENE:N,...",
                    help="run only these peer configurations, e.g. pile:27000,ball:1")
    ap.add_argument("--source", metavar="TEXT",
                    help="what rbsim source was measured (default: git describe of this tree)")
    ap.add_argument("--merge-from", metavar="CSV", action="append", default=[],
                    help="also report the rows of configurations not run now from an earlier peers.csv "
                         "(their ratios then compare runs made at different times); repeatable, "
                         "the first file that has an (engine, scene, N) gives its rows")
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
    if not os.path.exists(os.path.join(build, "bench", "peers", "peers_ode")):
        for e in ("ode", "ode_sap"):
            if e in engines:
                log(f"run.py: peers_ode was not built (no libode-dev): {e} is left out")
                engines.remove(e)
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
    streams = [run_stream(build)]
    layout = json.loads(subprocess.run([exe, "--layout"], capture_output=True, text=True).stdout)

    # Peer comparison: per configuration, repeats interleaved across engines.
    # The scaling runs that follow keep a reserve of the budget.
    expected = {}
    reserve = 0.0 if a.skip_scaling else (60.0 if a.quick else 240.0)
    if not a.skip_peers:
        only = set(a.only.split(",")) if a.only else None
        for scene, n, steps, reps in plan(a.quick):
            if only is not None and f"{scene}:{n}" not in only:
                continue
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
                    left = a.budget - (now() - t_start) - reserve - SETUP_ALLOW.get((e, n), 0)
                    if rep > 0:
                        prev = [x for x in rows if (x["scene"], x["n"], x["engine"]) == key]
                        if any(x["status"] != "ok" for x in prev):
                            continue  # capped or failed once: one run says it
                        if expected.get(key, 0) > left:
                            log(f"  skip {scene} {n} {e} rep {rep + 1}: budget")
                            continue
                    elif left < 20.0 and SETUP_ALLOW.get((e, n)):
                        log(f"  skip {scene} {n} {e}: its set-up alone would overrun the budget")
                        rows.append({"scene": scene, "n": n, "engine": e, "rep": 1,
                                     "status": "skipped (budget)", "steps_planned": steps})
                        continue
                    elif left < cap:
                        # first runs always happen, with the cap cut to what is left
                        cap = max(20.0, left)
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
        for engine, kind, n in scaling_plan(a.quick):
            if engine not in engines or (engine, kind) in stop:
                continue
            left = a.budget - (now() - t_start)
            if left < 30:
                log(f"  skip scaling {engine} {kind} {n}: budget")
                continue
            path = os.path.join(work, f"{kind}_{n}.bin")
            if not os.path.exists(path):
                scenes.write(path, kind, n)
            cap = min(10.0 if a.quick else 45.0, max(10.0, left / 6))
            # Set-up that grows faster than N would be killed anyway: predict it
            # from the last size of this series (as N^2, the worst seen).
            prev = [x for x in rows if x["engine"] == engine and x["scene"] == kind and x.get("setup_wall")]
            if prev:
                guess = prev[-1]["setup_wall"] * (n / prev[-1]["n"]) ** 2
                if guess > min(left, cap * 1.5 + 120):
                    log(f"  skip scaling {engine} {kind} {n}: set-up would take ~{guess:.0f} s "
                        f"(it grew as N^2 up to N = {prev[-1]['n']})")
                    rows.append({"scene": kind, "n": n, "engine": engine, "rep": 1,
                                 "steps_planned": scaling_steps(n),
                                 "status": f"skipped (set-up ~{guess:.0f} s predicted)"})
                    stop.add((engine, kind))
                    continue
            for rep in range(1, (1 if a.quick else scaling_reps(n)) + 1):
                if rep > 1 and a.budget - (now() - t_start) < 30:
                    log(f"  skip scaling {engine} {kind} {n} rep {rep}: budget")
                    break
                row = one_run(build, work, engine, kind, n, scaling_steps(n), cap, rep)
                rows.append(row)
                log(f"scaling {engine:9s} {kind:7s} n={n:7d} rep {rep}: {row['status']} {row.get('steps', 0)} steps, "
                    f"{row.get('ns_per_body_step', float('nan')):.0f} ns/body-step, "
                    f"{row['maxrss_kb'] / 1024:.0f} MB   [{now() - t_start:.0f} s]")
                if row["status"] != "ok":
                    stop.add((engine, kind))
                    break
        for name in os.listdir(work):
            if name.startswith(("lattice_", "stack_")):
                os.remove(os.path.join(work, name))

    # Bandwidth again at the end: the best of both is the machine's (others
    # share this machine; a busy moment only lowers a figure).
    streams.append(run_stream(build))
    stream = {k: max(x[k] for x in streams) for k in ("copy_gbs", "triad_gbs", "gflops_scalar")}
    stream["array_mb"] = streams[0]["array_mb"]
    stream["runs"] = streams
    total = now() - t_start
    log(f"total {total:.0f} s")
    notes = []
    # configurations (engine, scene, N) run now are kept; others come from the
    # first earlier file that has them
    taken = {(r["engine"], r["scene"], str(r["n"])) for r in rows}
    for path in a.merge_from:
        with open(path, newline="") as fh:
            old = [r for r in csv.DictReader(fh) if (r["engine"], r["scene"], r["n"]) not in taken]
        got = sorted({(r["engine"], r["scene"], r["n"]) for r in old})
        taken.update(got)
        rows += old
        if got:
            notes.append("Rows of " + ", ".join(f"{e} {sc} {n}" for e, sc, n in got) +
                         f" come from an earlier run of this benchmark ({os.path.basename(path)}, "
                         "given with --merge-from); ratios against them compare runs made at "
                         "different times, possibly on another machine (see Machine for this "
                         "run's): they are not same-run ratios.")
    write_csv(os.path.join(results, "peers.csv"), rows)
    git = subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"],
                         capture_output=True, text=True).stdout.strip()
    if git:
        top = os.path.join(HERE, "..", "..")
        dirty = subprocess.run(["git", "-C", top, "status", "--porcelain", "--", "lib"],
                               capture_output=True, text=True).stdout.strip()
        git += " (with uncommitted changes in lib/)" if dirty else " (lib/ as committed)"
    meta = {"machine": info, "stream": stream, "layout": layout, "quick": a.quick,
            "total_s": total, "engines": engines, "commit": a.source or git or "?",
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "notes": notes}
    with open(os.path.join(results, "peers_meta.json"), "w") as f:
        json.dump(meta, f, indent=1, sort_keys=True)
    import report
    report.write(results, meta)
    return 0


CSV_FIELDS = ["scene", "n", "engine", "rep", "status", "steps_planned", "steps", "sim_time",
              "wall", "setup_wall", "process_s", "cap_s", "wall_per_sim_s", "body_steps_per_s",
              "ns_per_body_step", "maxrss_kb", "rss_anon_kb", "escaped", "nonfinite", "max_ss_overlap_rel",
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
