"""``beveloid rating --plot``: S_F and S_H along the face of both members (ISO per section, the
local values as lines)."""
from __future__ import annotations

__all__ = ["safety_along_face"]


def safety_along_face(result, geometry, path, title=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f = result.factors
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.8), constrained_layout=True, sharey=True)
    for ax, (name, m) in zip(axes, result.members.items()):
        z = [s.face_z_mm for s in m.face]
        ax.plot(z, [s.safety_bending_iso for s in m.face], "C0-", label="S_F ISO")
        ax.plot(z, [s.safety_pitting_iso for s in m.face], "C1-", label="S_H ISO")
        for key, s in m.sections.items():
            ax.plot([s.face_z_mm], [s.safety_bending_iso], "C0o")
            ax.plot([s.face_z_mm], [s.safety_pitting_iso], "C1o")
            ax.annotate(key, (s.face_z_mm, s.safety_pitting_iso), textcoords="offset points", xytext=(0, 6),
                        ha="center", fontsize=8)
        if m.safety_bending is not None:
            ax.axhline(m.safety_bending, color="C0", ls="--", label="S_F local (FE root stress peak)")
            if m.root_stress_location is not None and m.root_stress_location["face_z_mm"] is not None:
                ax.plot([m.root_stress_location["face_z_mm"]], [m.safety_bending], "C0*", ms=11,
                        label="where the root stress peaks")
        if m.safety_pitting is not None:
            ax.axhline(m.safety_pitting, color="C1", ls="--", label="S_H local (LTCA peak)")
            at = result.loaded.peak_face_z_mm.get(name)
            if at is not None:
                ax.plot([at], [m.safety_pitting], "C1*", ms=11, label="where the peak's pair is centred")
        ax.axhline(f.S_Fmin, color="C0", ls=":", lw=1, label="S_Fmin")
        ax.axhline(f.S_Hmin, color="C1", ls=":", lw=1, label="S_Hmin")
        ax.set_xlabel(f"{name}: face coordinate z (mm), toe < 0 < heel")
        ax.set_title(name)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("safety factor")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="outside lower center", ncol=4)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
