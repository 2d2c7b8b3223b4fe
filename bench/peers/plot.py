"""Plots of the peer benchmark (matplotlib, no display needed).

    plot.py RESULTS_DIR      reads RESULTS_DIR/peers.csv, writes peers.png
                             and scaling.png beside it

peers.png: cost (wall seconds per simulated second, and nanoseconds per
body-step) against the number of spheres in the pile, log-log, one line per
engine; hollow markers are runs that hit their wall-time cap (they covered
less simulated time than planned).
scaling.png: rbsim's cost per body-step from 1e3 to 1e6 spheres (200 steps
up to 1e4, then 2e6/N down to 20, of a falling lattice and of a settled
stack); flat means linear scaling.
"""
import csv
import os
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"rbsim": "#c0392b", "rbsim_mt": "#f1948a", "rbsim_sel": "#e67e22", "rbsim_tol": "#7b241c", "rbsim_soft": "#8e44ad", "ode": "#2c7fb8", "ode_sap": "#7fb8d8", "bullet": "#31a354",
          "mujoco": "#756bb1"}


def load(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def fnum(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return None


def medians(rows, scene, field):
    """{engine: [(n, median, all_ok, planned steps)]} over rows of one scene."""
    out = {}
    keys = sorted({(r["engine"], int(r["n"])) for r in rows if r["scene"] == scene})
    for e, n in keys:
        sel = [r for r in rows if r["scene"] == scene and r["engine"] == e and int(r["n"]) == n]
        vals = [fnum(r[field]) for r in sel if fnum(r[field])]
        if vals:
            out.setdefault(e, []).append((n, statistics.median(vals),
                                          all(r["status"] == "ok" for r in sel),
                                          fnum(sel[0].get("steps_planned"))))
    return out


def plot_peers(rows, path):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, field, label in ((axes[0], "wall_per_sim_s", "wall time per simulated second (s)"),
                             (axes[1], "ns_per_body_step", "cost per body-step (ns)")):
        for e, pts in medians(rows, "pile", field).items():
            # solid between sizes simulated for the same planned time, dotted
            # to a size simulated for less (N = 27,000: the first 0.1 s only)
            full = max(p[3] or 0 for p in pts)
            main = [p for p in pts if (p[3] or 0) == full]
            ax.plot([p[0] for p in main], [p[1] for p in main], "-", color=COLORS.get(e, "k"), label=e)
            for a, b in zip(pts, pts[1:]):
                if (a[3] or 0) != (b[3] or 0):
                    ax.plot([a[0], b[0]], [a[1], b[1]], ":", color=COLORS.get(e, "k"))
            for x, y, ok, _ in pts:
                ax.plot([x], [y], "o", color=COLORS.get(e, "k"),
                        markerfacecolor=COLORS.get(e, "k") if ok else "white")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("spheres in the pile, N")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    fig.suptitle("Pile of N spheres in a 2 m box, dt = 1 ms (medians; hollow: run hit its time cap;\n"
                 "dotted: N = 27,000 simulated for the first 0.1 s only, mostly free fall)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_scaling(rows, path):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    labels = {"lattice": "falling lattice (no contacts)", "stack": "settled stack (resting contacts)"}
    any_pts = False
    for kind, color in (("lattice", "#2c7fb8"), ("stack", "#c0392b")):
        for engine, style in (("rbsim", "-"), ("rbsim_sel", "--"), ("rbsim_soft", ":")):
            pts = medians(rows, kind, "ns_per_body_step").get(engine, [])
            if not pts:
                continue
            any_pts = True
            xs, ys = [p[0] for p in pts], [p[1] for p in pts]
            ax.plot(xs, ys, style, color=color, label=f"{engine}: {labels[kind]}")
            for x, y, ok, _ in pts:
                ax.plot([x], [y], "o", color=color, markerfacecolor=color if ok else "white")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("spheres, N")
    ax.set_ylabel("rbsim cost per body-step (ns)")
    ax.set_title("rbsim scaling, 200 steps to N = 1e4, then 2e6/N down to 20 (hollow: capped)")
    ax.grid(True, which="both", alpha=0.3)
    if any_pts:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(results):
    rows = load(os.path.join(results, "peers.csv"))
    plot_peers(rows, os.path.join(results, "peers.png"))
    plot_scaling(rows, os.path.join(results, "scaling.png"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: plot.py RESULTS_DIR")
    main(sys.argv[1])
