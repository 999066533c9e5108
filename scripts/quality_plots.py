#!/usr/bin/python3
"""Histograms of a froth quality report, like the paper's Figures 7 and 8: the aspect ratio by
cell kind (Theorem 1's bound for interior cells drawn in) and the dihedral angles by edge class
(Lemma 6's bounds drawn in). Usage: quality_plots.py QUALITY.json OUTDIR. Writes aspect.png and
dihedral.png."""
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
    total = max(1, sum(hist["counts"]))
    ax.bar(edges, [c / total for c in hist["counts"]], width=width, align="edge", alpha=0.6, label=label)


def main(path, out):
    q = json.load(open(path))
    os.makedirs(out, exist_ok=True)

    fig, ax = plt.subplots(figsize=(7, 4))
    for kind, data in q["cells"].items():
        bars(ax, data["aspect_histogram"], f"{kind} ({data['count']} cells)")
    ax.axvline(q["bounds"]["theorem1_interior_aspect_max"], color="k", ls="--", lw=1,
               label="Theorem 1: interior bound 2")
    ax.set_xlabel("aspect ratio (outradius / inradius)")
    ax.set_ylabel("fraction of cells")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "aspect.png"), dpi=120)

    classes = q.get("dihedral_degrees", {})
    fig, axes = plt.subplots(1, max(1, len(classes)), figsize=(5 * max(1, len(classes)), 4), squeeze=False)
    for ax, (cls, data) in zip(axes[0], classes.items()):
        bars(ax, data["histogram"], f"{cls} ({data['edges']} edges)")
        if cls == "interior_interior":
            lo, hi = q["bounds"]["lemma6_interior_dihedral_degrees"]
        elif cls == "border_interior":
            lo, hi = q["bounds"]["lemma6_border_interior_dihedral_degrees"]
        else:
            lo = hi = None
        if lo is not None:
            ax.axvline(lo, color="k", ls="--", lw=1, label=f"Lemma 6: [{lo:g}, {hi:g}]")
            ax.axvline(hi, color="k", ls="--", lw=1)
        ax.set_xlabel("dihedral angle (degrees)")
        ax.set_ylabel("fraction of edges")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "dihedral.png"), dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
