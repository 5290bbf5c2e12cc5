"""The convergence plot of an optimization run: candidates' fitness and CMA-ES's step size."""

from __future__ import annotations

from pathlib import Path

from teamenv.optimize.cmaes_loop import OptimizeResult


def plot_convergence(result: OptimizeResult, path: str | Path) -> Path:
    """Write ``path`` (PNG): every candidate's fitness per generation (dots), their mean and
    best (lines), the goal-difference part where matches were played, and sigma (a fraction
    of each parameter's range) below."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    gens = [g for g in result.generations if g.told]
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 1]})
    xs, means, bests, gds = [], [], [], []
    for g in gens:
        values = [s["fitness"] for s in g.scores or ()]
        top.scatter([g.generation] * len(values), values, s=10, color="0.6", zorder=1)
        xs.append(g.generation)
        means.append(sum(values) / len(values))
        bests.append(max(values))
        gd = [s["goal_difference"] for s in g.scores or () if s["goal_difference"] is not None]
        gds.append(sum(gd) / len(gd) if gd else None)
    top.plot(xs, means, "o-", color="C0", label="mean of the generation")
    top.plot(xs, bests, "^-", color="C2", label="best of the generation")
    if any(v is not None for v in gds) and \
            result.definition.get("evaluator", {}).get("metric_weight", 0):
        top.plot(xs, gds, "s--", color="C1", label="mean goal difference part")
    top.set_ylabel("fitness (higher is better)")
    top.set_title(f"teamenv optimize {result.name!r}: {result.space.dimension} parameters, "
                  f"{result.matches} matches")
    top.grid(alpha=0.3)
    top.legend(fontsize=8)
    bottom.plot(xs, [g.sigma for g in gens], "o-", color="C3")
    bottom.xaxis.set_major_locator(MaxNLocator(integer=True))
    bottom.set_ylabel("sigma")
    bottom.set_xlabel("generation")
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
