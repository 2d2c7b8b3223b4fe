"""Writes bench/results/peers.md from peers.csv and peers_meta.json.

    report.py RESULTS_DIR     (run.py calls it; rerun it to re-render)
"""
import csv
import json
import math
import os
import statistics
import sys

import plot

ENGINES = ["rbsim", "rbsim_mt", "rbsim_sel", "rbsim_tol", "rbsim_soft", "ode", "ode_sap", "bullet", "mujoco"]
RBSIM = ("rbsim", "rbsim_mt", "rbsim_sel", "rbsim_tol", "rbsim_soft")
BASE_OF = {"rbsim_mt": "rbsim", "rbsim_sel": "rbsim", "rbsim_tol": "rbsim", "rbsim_soft": "rbsim", "ode_sap": "ode"}  # same program, same baseline memory
R_BALL, H_BALL, E_BALL = 0.1, 1.0, 0.5


SMALL_PILE = 125  # the pile the marginal memory per body is measured against



def aslr_note(rows):
    """What the runs say of address-space randomisation (peers_spawn)."""
    on = unknown = 0
    for r in rows:
        try:
            a = json.loads(r.get("extra") or "{}").get("aslr")
        except ValueError:
            a = None
        on += a == 1
        unknown += a is None
    if on == 0 and unknown == 0:
        return "it was off in every run."
    return (f"the system refused it in {on} run(s) (aslr 1 in peers.csv's extra) and {unknown} run(s) "
            "do not say (a launcher before it), whose peaks are noisier.")

def marginal_per_body(rows, engine, n):
    """(peak at N - peak on the pile of SMALL_PILE) / (N - SMALL_PILE), bytes,
    or None when either was not measured."""
    if n <= SMALL_PILE:
        return None
    big = med([f(r["maxrss_kb"]) for r in sel(rows, "pile", n, engine)])
    small = med([f(r["maxrss_kb"]) for r in sel(rows, "pile", SMALL_PILE, engine)])
    if big is None or small is None:
        return None
    return (big - small) * 1024.0 / (n - SMALL_PILE)


def anon_kb(row):
    """A run's anonymous resident memory at its end, kB (None if not reported)."""
    v = f(row.get("rss_anon_kb"))
    return v if v is not None and v >= 0 else None


def anon_per_body(rows, engine, n):
    """(anon on the pile of n - anon on the ball) / n, bytes, or None."""
    big = med([anon_kb(r) for r in sel(rows, "pile", n, engine)])
    small = med([anon_kb(r) for r in sel(rows, "ball", 1, BASE_OF.get(engine, engine))])
    if big is None or small is None:
        return None
    return (big - small) * 1024.0 / n


def f(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def med(vals):
    vals = [v for v in vals if v is not None]
    return statistics.median(vals) if vals else None


def fmt(v, digits=3):
    if v is None:
        return "–"
    if v == 0:
        return "0"
    if abs(v) >= 1e5 or abs(v) < 1e-3:
        return f"{v:.{digits - 1}e}"
    return f"{v:.{digits}g}"


def sel(rows, scene, n=None, engine=None):
    return [r for r in rows if r["scene"] == scene and (n is None or int(r["n"]) == n)
            and (engine is None or r["engine"] == engine)]


def status_note(rs):
    st = sorted({r["status"] for r in rs})
    return ", ".join(st)


def ratio_median(rows, scene, n, engine, ref="rbsim", field="wall_per_sim_s"):
    """Median over repeats of engine's cost / ref's cost in the same repeat
    (repeat k of one paired with repeat k of the other, or its first run)."""
    out = []
    for r in sel(rows, scene, n, engine):
        base = [b for b in sel(rows, scene, n, ref) if b["rep"] == r["rep"]] or sel(rows, scene, n, ref)
        if base and f(base[0][field]) and f(r[field]):
            out.append(f(r[field]) / f(base[0][field]))
    return med(out), len(out)


def peers_tables(rows, meta):
    L = []
    configs = []
    for r in rows:
        key = (r["scene"], int(r["n"]))
        if r["scene"] in ("ball", "billiards", "pile") and key not in configs:
            configs.append(key)
    engines = [e for e in ENGINES if any(r["engine"] == e for r in rows)]

    L.append("### Speed\n")
    L.append("Medians over repeats.  *cost* = wall seconds per simulated second; "
             "*speed-up* = the engine's cost / rbsim's cost in the same repeat (median), "
             "so above 1 means rbsim is faster; one column for rbsim's default method (auto: the "
             "soft step from 64 moving spheres on, so every pile, else Euler with global rollback), "
             "one for the same on two threads (rbsim_mt: `--threads 2`, a pool of one thread lent to the world; "
             "the same bits), one for RBS_METHOD_SELECTIVE and one for RBS_METHOD_EULER with "
             "slop 0.005 (rbsim_tol: impacts shallower than 0.5 % of the radius are not rolled back), "
             "and one for RBS_METHOD_SOFT (rbsim_soft: the soft step, 3 sub-steps a frame).  *simulated* = the simulated time "
             "a run covered (less than planned when the run hit its wall-time cap; then costs "
             "come from different phases of the motion and the ratio is marked †).\n")
    refs = [x for x in RBSIM if x in engines]
    L.append("| scene | N | engine | runs | simulated (s) | cost (s/s) | body-steps/s | ns/body-step | "
             + " | ".join(f"speed-up of {x}" for x in refs) + " | status |")
    L.append("|---|---:|---|---:|---:|---:|---:|---:|" + "---:|" * len(refs) + "---|")
    for scene, n in configs:
        sims = {}
        for e in engines:
            rs = sel(rows, scene, n, e)
            if rs:
                sims[e] = med([f(r["sim_time"]) for r in rs])
        for e in engines:
            rs = sel(rows, scene, n, e)
            if not rs:
                continue
            cells = []
            for ref in refs:
                if e in RBSIM:
                    cells.append("")
                    continue
                ratio, cnt = ratio_median(rows, scene, n, e, ref)
                dagger = ""
                if sims.get(ref) is not None and sims.get(e) is not None and abs(sims[ref] - sims[e]) > 1e-9:
                    dagger = " †"
                cells.append(fmt(ratio) + (dagger if ratio is not None else ""))
            L.append(f"| {scene} | {n} | {e} | {len(rs)} | {fmt(sims.get(e))} | "
                     f"{fmt(med([f(r['wall_per_sim_s']) for r in rs]))} | "
                     f"{fmt(med([f(r['body_steps_per_s']) for r in rs]))} | "
                     f"{fmt(med([f(r['ns_per_body_step']) for r in rs]))} | "
                     + " | ".join(cells) + f" | {status_note(rs)} |")
    L.append("")

    L.append("### Memory\n")
    L.append("Peak resident memory of each run's process (getrusage ru_maxrss, by peers_spawn, a small C launcher: a process forked straight from the Python runner would inherit the runner's high-water mark), "
             "median.  *per body* = (peak − the same engine's peak on the one-sphere ball "
             "scene) / N: what each extra sphere costs, without the interpreter and the "
             "libraries.  Python engines carry the interpreter (~50–70 MB) in their peak.  "
             f"*marginal* = (peak − the same engine's peak on the pile of {SMALL_PILE}) / (N − {SMALL_PILE}): "
             "the same, without what any pile costs whatever its size -- the code and library pages "
             "a pile touches and the ball does not (rbsim's soft step and detection, about 80 KB, "
             "and the C library's) and fixed-size tables.\n")
    L.append("*anon* = the process's anonymous resident memory (RssAnon of /proc/self/status: heap and private "
             "mappings, none of the shared code and data pages of the program and its libraries), read by each "
             "driver at the end of its run while the engine's world still exists, median; *anon per body* = "
             "(anon − the same engine's anon on the ball) / N.  Peak RSS, the issue's measure and the verdict, "
             "also counts the libraries' code pages, and how many of those a run maps varies by about 100 KB "
             "from run to run (the kernel maps file pages around each fault); anon does not, and for rbsim, "
             "which reserves everything when the world is made, it is also the peak.  ODE and the Python "
             "engines may free memory before the end, so theirs is at most their peak.  "
             "peers_spawn runs every engine with address-space randomisation off (personality(2)): "
             "with it on, where the libraries land changes which of their pages are mapped, and "
             "the same run's peak varied by about 0.3 MB; "
             + aslr_note(rows) + "\n")
    L.append("| N | engine | peak (MB) | per body (bytes) | per body / ODE's | marginal (bytes) | marginal / ODE's | anon (MB) | anon per body (bytes) | anon per body / ODE's |")
    L.append("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    base = {e: med([f(r["maxrss_kb"]) for r in sel(rows, "ball", 1, BASE_OF.get(e, e))])
            for e in engines}
    for scene, n in configs:
        if scene != "pile":
            continue
        per, marg, aper = {}, {}, {}
        for e in engines:
            rs = sel(rows, scene, n, e)
            pk = med([f(r["maxrss_kb"]) for r in rs])
            if pk is not None and base.get(e) is not None:
                per[e] = (pk - base[e]) * 1024.0 / n
            m = marginal_per_body(rows, e, n)
            if m is not None:
                marg[e] = m
            a = anon_per_body(rows, e, n)
            if a is not None:
                aper[e] = a
        for e in engines:
            rs = sel(rows, scene, n, e)
            if not rs:
                continue
            pk = med([f(r["maxrss_kb"]) for r in rs])
            an = med([anon_kb(r) for r in rs])
            rel = per[e] / per["ode"] if (per.get("ode") or 0) > 0 and e in per else None
            mrel = marg[e] / marg["ode"] if (marg.get("ode") or 0) > 0 and e in marg else None
            arel = aper[e] / aper["ode"] if (aper.get("ode") or 0) > 0 and e in aper else None
            L.append(f"| {n} | {e} | {fmt(pk / 1024 if pk else None)} | {fmt(per.get(e), 4)} | {fmt(rel)} | "
                     f"{fmt(marg.get(e), 4)} | {fmt(mrel)} | {fmt(an / 1024 if an else None)} | "
                     f"{fmt(aper.get(e), 4)} | {fmt(arel)} |")
    L.append("")

    L.append("### Quality at the end of the run\n")
    L.append("From the final state, the same program for every engine (peers_quality): "
             "*escaped* = centres behind a plane (outside the box or through the floor) or not "
             "finite; worst overlaps relative to the radius (sphere–sphere: relative to the "
             "smaller radius); *> 1 %* = pairs / sphere–plane contacts overlapping by more than "
             "1 % of the radius; energy = kinetic + rotational + m g z at the end (J).  Medians "
             "over repeats (worst case for escaped).\n")
    L.append("| scene | N | engine | simulated (s) | escaped | worst s–s overlap | worst s–plane overlap | s–s > 1 % | s–plane > 1 % | energy (J) |")
    L.append("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for scene, n in configs:
        for e in engines:
            rs = [r for r in sel(rows, scene, n, e) if r.get("escaped") not in (None, "")]
            if not rs:
                continue
            esc = max(int(float(r["escaped"])) for r in rs)
            ss = med([f(r["max_ss_overlap_rel"]) for r in rs])
            sp = med([f(r["max_sp_overlap_rel"]) for r in rs])
            L.append(f"| {scene} | {n} | {e} | {fmt(med([f(r['sim_time']) for r in rs]))} | {esc} | "
                     f"{fmt(100 * ss if ss is not None else None)} % | "
                     f"{fmt(100 * sp if sp is not None else None)} % | "
                     f"{fmt(med([f(r['ss_over_1pct']) for r in rs]))} | "
                     f"{fmt(med([f(r['sp_over_1pct']) for r in rs]))} | "
                     f"{fmt(med([f(r['energy']) for r in rs]), 6)} |")
    L.append("")

    # bouncing ball
    L.append("### Bouncing ball: apex heights\n")
    L.append(f"Ball of radius {R_BALL} m dropped from rest with its lowest point {H_BALL} m above "
             f"the floor, e = {E_BALL}.  Apex n (height of the lowest point) should be "
             "h e^(2n): 0.25, 0.0625, 0.015625 m.  Relative errors in brackets; first repeat "
             "(every repeat is identical for a deterministic engine).\n")
    L.append("| engine | apex 1 (m) | apex 2 (m) | apex 3 (m) |")
    L.append("|---|---:|---:|---:|")
    for e in engines:
        rs = sel(rows, "ball", 1, e)
        if not rs:
            continue
        ap = [float(x) - R_BALL for x in rs[0].get("apex", "").split(";") if x]
        cells = []
        for k in range(3):
            exact = H_BALL * E_BALL ** (2 * (k + 1))
            if k < len(ap):
                cells.append(f"{ap[k]:.5f} ({100 * (ap[k] - exact) / exact:+.1f} %)")
            else:
                cells.append("no bounce")
        L.append(f"| {e} | " + " | ".join(cells) + " |")
    L.append("")
    return L


def machine_limit(rows, meta):
    L = []
    st, lay = meta["stream"], meta["layout"]
    bw = st["triad_gbs"] * 1e9
    gf = st["gflops_scalar"] * 1e9
    cb = lay["contact_bytes"]
    state_b = 2 * 13 * 8 + 3 * 8
    L.append("### How close rbsim comes to the machine's limit\n")
    L.append(f"Measured on one core by `peers_stream` (STREAM-like, 128 MB arrays, best of 10 passes, "
             f"best of the runs at the start and the end of the benchmark): "
             f"copy {st['copy_gbs']:.1f} GB/s, triad {st['triad_gbs']:.1f} GB/s; "
             f"{st['gflops_scalar']:.1f} GFLOP/s for 8 independent multiply-add chains.\n")
    L.append("Bytes a body-step must move at the least, from rbsim's state layout "
             "(`lib/src/core/world_internal.h`, structure of arrays of doubles): position 3, "
             "velocity 3, angular velocity 3, orientation 4 doubles read and written once "
             f"(2 × 104 B) plus radius, inverse mass and inverse inertia read (24 B) = {state_b} B; "
             f"each contact slot ({cb:.0f} B, measured from `rbs_world_memory_size` by "
             "`peers_rbsim --layout`) written once when found and read once by the solver, "
             f"{2 * cb:.0f} B per contact.  The world holds {lay['body_bytes']:.0f} B per body "
             f"plus {cb:.0f} B per contact slot ({lay['body_bytes_with_default_contacts']:.0f} B "
             "per body with the default 4 contact slots per body).  This is a floor: the "
             "rollback's two state saves, the broad phase's arrays and every extra solver sweep "
             "add to it.  Arithmetic floor: ~60 flops per body (integration, quaternion), ~120 "
             "per contact (one normal + friction impulse), rough.\n")
    L.append("| scene | N | rbsim | contacts per body | bytes/body-step (floor) | bound from bandwidth (body-steps/s) | bound from arithmetic | rbsim measured | fraction of the tighter bound |")
    L.append("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for eng, scene in [(x, y) for x in RBSIM for y in ("pile", "lattice", "stack")]:
        ns = sorted({int(r["n"]) for r in sel(rows, scene, engine=eng)})
        for n in ns:
            rs = sel(rows, scene, n, eng)
            meas = med([f(r["body_steps_per_s"]) for r in rs])
            cpb = []
            for r in rs:
                try:
                    x = json.loads(r["extra"] or "{}")
                    cpb.append(x.get("contacts_max", 0) / n)
                except ValueError:
                    pass
            c = med(cpb) or 0.0
            bytes_ = state_b + c * 2 * cb
            bbw = bw / bytes_
            bfl = gf / (60 + 120 * c)
            tight = min(bbw, bfl)
            L.append(f"| {scene} | {n} | {eng} | {fmt(c)} | {fmt(bytes_, 4)} | {fmt(bbw)} | {fmt(bfl)} | "
                     f"{fmt(meas)} | {fmt(meas / tight if meas else None)} |")
    L.append("")
    return L


def scaling_runs(rows, scene, eng):
    """The runs of each N of a scaling series, in order of N."""
    by_n = {}
    for r in sel(rows, scene, engine=eng):
        by_n.setdefault(int(r["n"]), []).append(r)
    return [by_n[n] for n in sorted(by_n)]


def median_run(rs):
    """The median run by cost (of an even count, the lower; runs without a
    cost -- skipped, failed -- only when no run has one)."""
    costed = sorted((r for r in rs if f(r["ns_per_body_step"])), key=lambda r: f(r["ns_per_body_step"]))
    return costed[(len(costed) - 1) // 2] if costed else rs[0]


def scaling_table(rows):
    L = []
    if not any(r["scene"] in ("lattice", "stack") for r in rows):
        return L
    L.append("### rbsim alone from 10^3 to 10^6 spheres\n")
    L.append("200 steps up to N = 10^4, then 2·10^6 / N down to 20 from N = 10^5 (dt = 1 ms; "
             "run.py's scaling_steps: 20 steps of 1,000 spheres take 2 ms, mostly the first "
             "step's one-off work) of a falling lattice (10 layers, spacing 0.12 m, no contacts "
             "yet) and of a settled stack (10 layers of touching spheres on the floor, walls "
             "touching: every sphere in resting contact), with rbsim's default method (auto: soft "
             "at these sizes), with RBS_METHOD_SOFT and with RBS_METHOD_SELECTIVE.  Target: flat cost per body-step.  "
             "Seven runs each up to N = 30,000 and three beyond (run.py's scaling_reps; the runs column "
             "says how many), one after another: each line is the median run "
             "by cost, with the range of the runs' costs; a run that "
             "hits its wall-time cap (status capped: fewer steps than planned) stops the larger sizes "
             "of that scene and method.\n")
    L.append("| rbsim | scene | N | runs | status | steps | wall (s) | setup (s) | ns/body-step | range | vs N = 1000 | peak MB | bytes/body | substeps | rollbacks | contacts |")
    L.append("|---|---|---:|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|")
    for eng in RBSIM:
        for scene in ("lattice", "stack"):
            first = None
            for rs in scaling_runs(rows, scene, eng):
                r = median_run(rs)
                n = int(r["n"])
                c = f(r["ns_per_body_step"])
                costs = [f(x["ns_per_body_step"]) for x in rs if f(x["ns_per_body_step"])]
                spread = f"{fmt(min(costs))}-{fmt(max(costs))}" if len(costs) > 1 else "–"
                if first is None and c:
                    first = c
                try:
                    x = json.loads(r["extra"] or "{}")
                except ValueError:
                    x = {}
                pk = f(r["maxrss_kb"])
                L.append(f"| {eng} | {scene} | {n} | {len(rs)} | {r['status']} | {r['steps'] or '–'} | {fmt(f(r['wall']))} | "
                         f"{fmt(f(r['setup_wall']))} | {fmt(c)} | {spread} | {fmt(c / first if c and first else None)} | "
                         f"{fmt(pk / 1024 if pk else None)} | {fmt(pk * 1024 / n if pk else None, 4)} | "
                         f"{x.get('substeps', '–')} | {x.get('rollbacks', '–')} | {x.get('contacts_max', '–')} |")
    L.append("")
    L.append("![rbsim scaling](scaling.png)\n")
    return L


def targets(rows, meta):
    L = ["### Against the targets of issue 9\n"]
    L.append("For rbsim's default method (**rbsim**, RBS_METHOD_AUTO: the soft step on every pile "
             "here, Euler on the ball and the billiards), for the same on two threads (**rbsim_mt**, the same bits; "
             "the others step on one thread, as ODE does), for RBS_METHOD_SELECTIVE (**rbsim_sel**) and for "
             "RBS_METHOD_EULER with slop 0.005 (**rbsim_tol**, `simulation.slop` in a scene) and for "
             "RBS_METHOD_SOFT (**rbsim_soft**, `\"method\": \"soft\"` in a scene: the soft step); "
             "ODE is ODE with the issue's dHashSpace (ratios against ode_sap are in the speed "
             "table).\n")
    for eng in RBSIM:
        if not any(r["engine"] == eng for r in rows):
            continue
        for n in (1000, 8000):
            r, cnt = ratio_median(rows, "pile", n, "ode", eng)
            verdict = "not measured" if r is None else ("met" if r >= 10 else "NOT met")
            sims = {e: med([f(x["sim_time"]) for x in sel(rows, "pile", n, e)]) for e in (eng, "ode")}
            note = ""
            if r is not None and sims[eng] is not None and sims["ode"] is not None and abs(sims[eng] - sims["ode"]) > 1e-9:
                note = (f" († {eng} covered only {fmt(sims[eng])} s of simulated time before its cap, "
                        f"ODE {fmt(sims['ode'])} s)")
            L.append(f"- {eng}: at least 10× ODE's speed at N = {n}: measured {fmt(r)}× — {verdict}{note}.")
        sc = []
        for scene in ("lattice", "stack"):
            pts = [(int(r["n"]), f(r["ns_per_body_step"]), r["status"])
                   for r in (median_run(rs) for rs in scaling_runs(rows, scene, eng))]
            pts = sorted(p for p in pts if p[1])
            if pts:
                ok_pts = [p for p in pts if p[2] == "ok"]
                spread = max(p[1] for p in pts) / min(p[1] for p in pts)
                sc.append(f"{scene} {fmt(pts[0][1])} ns at N = {pts[0][0]} to {fmt(pts[-1][1])} ns at "
                          f"N = {pts[-1][0]} (max/min {fmt(spread)}; largest N completed: "
                          f"{ok_pts[-1][0] if ok_pts else 'none'})")
        L.append(f"- {eng}: cost per body-step flat from 10^3 to 10^6: " + ("; ".join(sc) if sc else "not measured") + ".")
        base = {e: med([f(r["maxrss_kb"]) for r in sel(rows, "ball", 1, BASE_OF.get(e, e))]) for e in (eng, "ode")}
        for n in (1000, 8000, 27000):
            pr = med([f(r["maxrss_kb"]) for r in sel(rows, "pile", n, eng)])
            po = med([f(r["maxrss_kb"]) for r in sel(rows, "pile", n, "ode")])
            if pr and po and base[eng] and base["ode"] and po - base["ode"] > 0:
                rel = (pr - base[eng]) / (po - base["ode"])
                L.append(f"- {eng}: peak memory per body at most 1/5 of ODE's, N = {n}: {fmt(rel)} of ODE's "
                         f"— {'met' if rel <= 0.2 else 'NOT met'}.")
            mr, mo = marginal_per_body(rows, eng, n), marginal_per_body(rows, "ode", n)
            if mr is not None and mo:
                L.append(f"  (marginal, against the pile of {SMALL_PILE}: {fmt(mr / mo)} of ODE's — "
                         f"{'within' if mr / mo <= 0.2 else 'beyond'} 1/5; "
                         "the line above is the verdict)")
            ar, ao = anon_per_body(rows, eng, n), anon_per_body(rows, "ode", n)
            # (ODE's peak per body, to tell whether its anon at the end still holds its step memory)
            op = (po - base["ode"]) * 1024.0 / n if po and base["ode"] else None
            if ar is not None and ao and op and ao < 0.5 * op:
                L.append(f"  (anonymous memory at the end of the run: not comparable here — ODE's, "
                         f"{fmt(ao)} bytes a body, is under half its peak's {fmt(op)}: it had freed its "
                         f"step memory by then; rbsim's is {fmt(ar)} bytes, its peak too)")
            elif ar is not None and ao:
                L.append(f"  (anonymous memory at the end of the run, without shared code pages: {fmt(ar / ao)} "
                         f"of ODE's — {'within' if ar / ao <= 0.2 else 'beyond'} 1/5; the peak-RSS line above "
                         "is the verdict)")
        for n in (1000, 8000, 27000):
            rs = [r for r in sel(rows, "pile", n, eng) if r.get("escaped") not in (None, "")]
            if rs:
                esc = max(int(float(r["escaped"])) for r in rs)
                ss = max(f(r["max_ss_overlap_rel"]) or 0 for r in rs)
                sp = max(f(r["max_sp_overlap_rel"]) or 0 for r in rs)
                ok = esc == 0 and ss <= 0.01 and sp <= 0.01
                simt = med([f(r["sim_time"]) for r in rs])
                L.append(f"- {eng}: no sphere escaping or overlapping by more than 1 % of its radius, N = {n} "
                         f"(worst repeat, at t = {fmt(simt)} s): escaped {esc}, sphere–sphere {100 * ss:.3g} %, "
                         f"sphere–plane {100 * sp:.3g} % — {'met' if ok else 'NOT met'}.")
    L.append("")
    return L


HEADER = """# Peer benchmark: rbsim against ODE, Bullet and MuJoCo

**Command** (from the repository root; builds what it needs with meson in `./build`):

    bench/peers/run.sh            # full run, < 40 minutes on this 2-core machine
    bench/peers/run.sh --quick    # N = 1000 only, 0.5 s simulated, one repeat (~1 minute)

**Installs it needs** (not part of the test setup):

    apt-get install -y libode-dev
    .venv/bin/python -m pip install pybullet mujoco matplotlib      # .venv made by `bash .ci/setup`

Files: `peers.csv` (every run), `peers_meta.json` (machine, bandwidth, layout), this file,
`peers.png`, `scaling.png`.  Sources and the exact settings of every engine: `bench/peers/`.
"""

SETTINGS = """### The scenes and each engine's settings

Scenes (one file per scene, written by `bench/peers/scenes.py`, read by all four drivers):

- **pile N**: N spheres (r = 0.05 m, m = 0.1 kg) on a lattice of spacing 0.12 m, at most
  16 × 16 per layer (so N = 8000 is 32 layers, 27,000 is 106 layers), lowest centres at
  z = 0.1 m, each coordinate jittered by up to ±5 mm (splitmix64 of the index, deterministic),
  dropped at rest into a 2 m × 2 m box (floor z = 0, walls x, y = ±1 facing inward).
  N = 1000 and 8000: 2 s simulated.  **N = 27,000: 0.1 s simulated** (ODE alone needs minutes
  per simulated second); in 0.1 s only the lowest layers have landed.
- **billiards**: 16 balls (r = 0.0286 m, m = 0.17 kg) on a floor, a triangle of 15 with
  0.1 mm gaps and the cue ball at 8 m/s; 2 s.
- **ball**: r = 0.1 m, 1 kg, dropped from 1 m (lowest point), 2 s.
- Every contact: restitution e = 0.5, friction μ = 0.5; gravity 9.81 m/s²; dt = 1 ms; no
  damping anywhere.  Only the stepping loop is timed (creation is reported as setup).

Engines:

- **rbsim** (this repository, the commit named below): `rbs_world_def` defaults (method auto: soft on the piles, Euler on ball and billiards,
  slop 1e-6 r, max_halvings 30, max_sweeps 20, contact slots 4 per body + 16), one "*"/"*"
  material pair with μs = μk = 0.5, e = 0.5.
- **ODE** (Debian libode-dev, double precision, C API): dHashSpace at its default levels
  (the issue's choice; **ode_sap** is the same driver with dSweepAndPruneSpace, which is faster
  for these scenes, run at N ≤ 8000 so that the comparison is fair to ODE), dWorldQuickStep with 20 iterations, ERP 0.2, CFM 1e-5, contact surface layer 0, no
  auto-disable; one contact point per pair, dContactBounce | dContactApprox1 (friction pyramid,
  μ as a Coulomb coefficient), μ = 0.5, bounce 0.5, bounce_vel 0.01 m/s (≈ g dt).
- **Bullet** (PyPI pybullet, DIRECT mode): setTimeStep(0.001), pybullet's defaults otherwise
  (50 solver iterations, sleeping allowed after 2 s at rest); spheres as rigid bodies
  (useMaximalCoordinates) made in batches from one shape; planes as static GEOM_PLANE.  Bullet
  multiplies the two bodies' coefficients, so each body gets restitution and lateral friction
  √0.5 — each contact then has exactly 0.5; rolling/spinning friction 0, damping 0 (pybullet's
  default damping is 0.04).
- **MuJoCo** (PyPI mujoco): MJCF generated by the driver, one free body + sphere geom per
  sphere, plane geoms for floor and walls; timestep 0.001, Euler, pyramidal cone, condim 3,
  default solver (Newton, 100 iterations); soft contacts with solref = (0.02 s, 0.2154):
  MuJoCo's default time constant and the damping ratio ζ whose spring-damper bounce gives
  e = exp(−πζ/√(1−ζ²)) = 0.5; solimp default.  This approximates restitution only (see the
  bouncing ball).
"""


CAVEATS = """### Reading the numbers

- Costs are for the stepping loop only.  Runs that hit their wall-time cap (status *capped*)
  cover less simulated time than planned; their cost comes from an earlier, cheaper or dearer,
  phase of the motion (free fall is cheap, a settled pile dear), so ratios against them (†) are
  not like for like.  The pile at N = 27,000 covers only its first 0.1 s (mostly free fall).
- The ball and billiards scenes measure per-step overhead more than physics: Bullet's and
  MuJoCo's drivers call into the engine from Python once per step (and, for the ball, read its
  state every step to find the apexes), which costs microseconds per step.
- Bullet's bouncing ball stops at the second impact: with pybullet's defaults the contact is
  found within Bullet's contact margin before the ball touches, and that contact takes the
  impact without restitution.  MuJoCo's bounce overshoots (its contacts are soft, see the
  solref choice); its overlaps in the pile are the same softness under load.
- ODE's collision spaces: the issue names dHashSpace; at default levels it is faster here than
  levels fitted to the spheres; ode_sap (sweep and prune) is also shown.
- This is a shared 2-core virtual machine on which other builds and tests were running: runs of
  the same configuration differ by up to ×2 at busy moments.  Ratios compare runs made next to
  each other (engines alternate run by run), which cancels most of that.
"""


def write(results, meta=None):
    if meta is None:
        with open(os.path.join(results, "peers_meta.json")) as fh:
            meta = json.load(fh)
    with open(os.path.join(results, "peers.csv"), newline="") as fh:
        rows = list(csv.DictReader(fh))
    m = meta["machine"]
    L = [HEADER]
    L.append(f"**This run**: {meta.get('date', '?')}, rbsim commit {meta.get('commit', '?')}, "
             f"{'QUICK mode' if meta.get('quick') else 'full mode'}, {meta['total_s']:.0f} s in all.\n")
    L.append(f"**Machine**: {m['cpu']} ({m.get('simd', '')}), `nproc` = {m['nproc']}, "
             f"{m['memory']} memory, cache {m.get('cache', '?')}, Linux {m['kernel']}, {m['cc']}, "
             f"Python {m['python']}; versions: "
             + ", ".join(f"{k} {v}" for k, v in sorted(m.get("versions", {}).items()))
             + ".  A shared 2-core virtual machine: expect ±10–20 % noise between runs.\n")
    L.append("## Results\n")
    L.append("![cost against N](peers.png)\n")
    L += targets(rows, meta)
    L += peers_tables(rows, meta)
    L += machine_limit(rows, meta)
    L += scaling_table(rows)
    L.append(SETTINGS)
    L.append(CAVEATS)
    notes = meta.get("notes")
    if notes:
        L.append("### Notes\n")
        L += [f"- {x}" for x in notes]
        L.append("")
    with open(os.path.join(results, "peers.md"), "w") as fh:
        fh.write("\n".join(L))
    plot.main(results)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: report.py RESULTS_DIR")
    write(sys.argv[1])
