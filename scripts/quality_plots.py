#!/usr/bin/python3
"""Histograms of a froth quality report, like the paper's Figures 7 and 8: the aspect ratio by
cell kind (Theorem 1's bound for interior cells drawn in) and the dihedral angles by edge class
(Lemma 6's bounds drawn in). Counts are on a log scale, so the few cells outside a bound show;
values beyond the histogram's range are counted on the plot, not cut off.

Usage: quality_plots.py QUALITY.json OUTDIR [TITLE]. Writes OUTDIR/aspect.png and dihedral.png."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def bars(ax, hist, label):
    n = len(hist["counts"])
    width = (hist["hi"] - hist["lo"]) / n
    edges = [hist["lo"] + i * width for i in range(n)]
    ax.bar(edges, hist["counts"], width=width, align="edge", alpha=0.6, label=label)


def beyond(ax, hists, what):
    """Notes on the plot how many values fall outside its range."""
    below = sum(h.get("below", 0) for h in hists)
    above = sum(h.get("above", 0) for h in hists)
    lo, hi = hists[0]["lo"], hists[0]["hi"]
    notes = []
    if below:
        notes.append(f"{below} {what} below {lo:g}")
    if above:
        notes.append(f"{above} {what} at or above {hi:g} (not drawn)")
    if notes:
        ax.text(0.98, 0.97, "\n".join(notes), transform=ax.transAxes, ha="right", va="top", fontsize=8,
                bbox={"facecolor": "white", "edgecolor": "0.6"})


def finish(ax, xlabel, ylabel):
    ax.set_yscale("log")
    ax.set_ylim(bottom=0.5)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8, loc="upper left")


def main(path, out, title):
    q = json.load(open(path))
    os.makedirs(out, exist_ok=True)
    title = title or q.get("mesh", "")

    fig, ax = plt.subplots(figsize=(7, 4.5))
    hists = []
    for kind, data in q["cells"].items():
        bars(ax, data["aspect_histogram"], f"{kind} ({data['count']} cells)")
        hists.append(data["aspect_histogram"])
    ax.axvline(q["bounds"]["theorem1_interior_aspect_max"], color="k", ls="--", lw=1,
               label="Theorem 1: interior cells at most 2")
    if hists:
        beyond(ax, hists, "cells")
    finish(ax, "aspect ratio (outradius / inradius)", "cells")
    ax.set_title(f"{title}\naspect ratio by cell kind", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "aspect.png"), dpi=120)
    plt.close(fig)

    classes = q.get("dihedral_degrees", {})
    fig, axes = plt.subplots(1, max(1, len(classes)), figsize=(5 * max(1, len(classes)), 4.5), squeeze=False)
    for ax, (cls, data) in zip(axes[0], classes.items()):
        bars(ax, data["histogram"], f"{cls.replace('_', '-')} ({data['edges']} edges)")
        bound = {"interior_interior": "lemma6_interior_dihedral_degrees",
                 "border_interior": "lemma6_border_interior_dihedral_degrees"}.get(cls)
        if bound:
            lo, hi = q["bounds"][bound]
            ax.axvline(lo, color="k", ls="--", lw=1, label=f"Lemma 6: [{lo:g}, {hi:g}]")
            ax.axvline(hi, color="k", ls="--", lw=1)
        beyond(ax, [data["histogram"]], "edges")
        finish(ax, "dihedral angle (degrees)", "edges")
    fig.suptitle(f"{title}\ndihedral angles by edge class", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "dihedral.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) == 4 else "")
