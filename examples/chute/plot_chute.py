#!/usr/bin/env -S /usr/bin/python3
"""The chute of examples/chute/chute.toml: a side view of a frame (the beads coloured by
their speed) and the beads that left through the open end over time.

    PYTHONPATH=build/python python3 examples/chute/plot_chute.py OUT_DIR [--png PATH] [--frame I]

--frame picks the frame drawn (default: the middle one, the flow under way). Writes
OUT_DIR/chute.png (default) and prints the beads gone and the peak discharge rate.
"""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from tsubu.pictures import discharge_run, draw_grains, save_figure  # noqa: E402


def main():
    args, run, frame = discharge_run(__doc__.splitlines()[0])
    gone_t, gone_m = np.asarray(run.outflow["time"], float), np.asarray(run.outflow["mass"], float)
    print(f"{len(gone_t)} beads left through the open end by t = {run.series['time'][-1]:.2f} s "
          f"({gone_m.sum() * 1e3:.2f} g)")

    fig, (ax, ax_out) = plt.subplots(2, 1, figsize=(10, 6.5), gridspec_kw={"height_ratios": [1, 1]})
    fig.colorbar(draw_grains(ax, frame), ax=ax, label="speed (m/s)", shrink=0.9)
    summary = run.summary or {}
    lo, hi = summary.get("domain", {}).get("lower", [0, 0, 0]), summary.get("domain", {}).get("upper", [0.12, 0, 0.04])
    ax.axvline(hi[0], color="tab:red", lw=1, ls="--", label="open end (x_max)")
    ax.set_xlim(lo[0], hi[0] + 0.005)
    ax.set_ylim(lo[2], hi[2])
    ax.set_aspect("equal")
    ax.set_xlabel("x along the chute (m)")
    ax.set_ylabel("z (m)")
    ax.legend(loc="upper right", fontsize="small")
    ax.set_title(f"t = {frame.time:.2f} s (gravity tilted 30°: the chute's frame)", fontsize="medium")
    bins = np.arange(0, run.series["time"][-1] + 0.02, 0.02)
    rate, _ = np.histogram(gone_t, bins=bins, weights=gone_m)
    ax_out.step(bins[:-1], rate / 0.02 * 1e3, where="post", color="k", label="discharge rate (g/s, per 20 ms)")
    ax_out.set_xlabel("t (s)")
    ax_out.set_ylabel("discharge rate (g/s)")
    ax_cum = ax_out.twinx()
    ax_cum.plot(run.series["time"], run.series["outflow_count"], "tab:blue", label="beads gone")
    ax_cum.set_ylabel("beads gone", color="tab:blue")
    ax_out.grid(alpha=0.3)
    ax_out.legend(loc="upper left", fontsize="small")
    print(f"peak discharge rate {rate.max() / 0.02 * 1e3:.1f} g/s")
    save_figure(fig, args.png or os.path.join(args.out_dir, "chute.png"), "Chute with an open end (examples/chute/chute.toml)")


if __name__ == "__main__":
    main()
