"""The matplotlib style shared by mfcd's post scripts: one place for fonts and resolutions.

    from mfcd_style import figure_style
    plt.rcParams.update(figure_style(savefig_dpi=150))
"""

BASE = {
    "font.size": 11,
    "axes.titlesize": 11,
    "axes.labelsize": 11,
    "legend.fontsize": 9,
    "xtick.labelsize": 10,
    "ytick.labelsize": 10,
    "figure.dpi": 100,
    "savefig.dpi": 120,
}


def figure_style(**overrides) -> dict:
    """BASE with overrides; a keyword's underscores stand for the rcParams' dots
    (savefig_dpi= sets "savefig.dpi")."""
    style = dict(BASE)
    style.update({k.replace("_", "."): v for k, v in overrides.items()})
    return style
