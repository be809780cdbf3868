"""The charts of report.py (matplotlib, files only): speed against accuracy with its Pareto front,
and lines of a value over a parameter. One colour per method across every chart of a report."""
import matplotlib

matplotlib.use("Agg")  # no display: files only
import matplotlib.pyplot as plt  # noqa: E402

# One colour per method, stable across every chart of a report.
METHOD_COLOURS = {
    "ref": "#555555", "sm": "#1f77b4", "pcf": "#17becf", "pcss": "#9467bd", "msm": "#8c564b",
    "srt": "#d62728", "frt": "#ff7f0e", "ls": "#2ca02c", "bitmask": "#e377c2",
}
EXTRA_COLOURS = ["#bcbd22", "#7f7f7f", "#aec7e8", "#98df8a", "#ff9896"]

ERROR_LABELS = {
    "rmse": "RMSE of the visibility vs the Embree reference",
    "wrong_pixel_fraction": "wrong-pixel fraction vs the Embree reference",
    "mae": "MAE of the visibility vs the Embree reference",
    "max": "max |error| of the visibility vs the Embree reference",
}


def colour(method, _cache={}):
    if method in METHOD_COLOURS:
        return METHOD_COLOURS[method]
    if method not in _cache:
        _cache[method] = EXTRA_COLOURS[len(_cache) % len(EXTRA_COLOURS)]
    return _cache[method]


def pareto_front(points):
    """Points (error, time) not dominated by another (one that is no worse in both and better in one)."""
    front = []
    for p in points:
        dominated = any(q is not p and q["error"] <= p["error"] and q["time"] <= p["time"] and
                        (q["error"] < p["error"] or q["time"] < p["time"]) for q in points)
        if not dominated:
            front.append(p)
    return sorted(front, key=lambda p: (p["error"], p["time"]))


def speed_accuracy_chart(points, path, title, error_key="rmse", max_error=None, chosen=None, reference_ms=None):
    """One point per method/parameter set: error (x) against median frame time (y, min-max as a bar).

    points: dicts with label, method, error, time, tmin, tmax. The Pareto frontier joins the
    points no other point beats in both time and error.
    """
    fig, ax = plt.subplots(figsize=(7.5, 5.0), dpi=100)
    usable = [p for p in points if p["error"] is not None and p["time"] is not None]
    positive = [p["error"] for p in usable if p["error"] > 0]
    floor = min(positive) if positive else 1e-6
    for method in dict.fromkeys(p["method"] for p in usable):
        mine = [p for p in usable if p["method"] == method]
        ax.errorbar([p["error"] for p in mine], [p["time"] for p in mine],
                    yerr=[[p["time"] - p["tmin"] for p in mine], [p["tmax"] - p["time"] for p in mine]],
                    fmt="o", color=colour(method), ecolor=colour(method), elinewidth=1, capsize=2,
                    markersize=7, label=method, zorder=3)
    for p in usable:
        ax.annotate(p["label"], (p["error"], p["time"]), textcoords="offset points", xytext=(5, 4), fontsize=7,
                    color="#333333")
    front = pareto_front(usable)
    if len(front) >= 1:
        xs, ys = [], []
        for p in front:
            xs.append(p["error"])
            ys.append(p["time"])
        ax.step(xs, ys, where="post", color="#222222", linewidth=1.2, linestyle="--", zorder=2)
        # Rings mark the frontier's points, so a frontier of one point (one method beats all) shows too.
        ax.plot(xs, ys, linestyle="none", marker="o", markersize=13, markerfacecolor="none", markeredgecolor="#222222",
                label="Pareto frontier (ringed)", zorder=2)
    if max_error is not None:
        ax.axvline(max_error, color="#2ca02c", linewidth=1.5, label=f"max error {max_error:g}")
    if chosen is not None:
        ax.plot([chosen["error"]], [chosen["time"]], marker="*", markersize=20, color="#ffd700",
                markeredgecolor="black", linestyle="none", label=f"chosen: {chosen['label']}", zorder=4)
    if reference_ms is not None:
        ax.axhline(reference_ms, color=colour("ref"), linewidth=1, linestyle=":", label="ref (Embree) time")
    # Exact methods have error 0: a linear segment around 0, logarithmic above the smallest error.
    ax.set_xscale("symlog", linthresh=floor, linscale=0.5)
    ax.set_xlim(left=-0.05 * floor)
    times = [p["time"] for p in usable] + ([reference_ms] if reference_ms else [])
    if times and min(times) > 0 and max(times) / min(times) > 20:
        ax.set_yscale("log")
    ax.set_xlabel(ERROR_LABELS.get(error_key, error_key) + " (0 = exact)")
    ax.set_ylabel("frame time, ms (median; bar: min-max)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def line_chart(series, path, title, xlabel, ylabel, logx=False, logy=False):
    """series: {label: (method, [(x, y), ...])}."""
    fig, ax = plt.subplots(figsize=(7.0, 4.5), dpi=100)
    seen = {}  # configurations of one method share its colour and differ in line style and marker
    for label, (method, xy) in series.items():
        xy = sorted(p for p in xy if p[1] is not None)
        if not xy:
            continue
        k = seen[method] = seen.get(method, -1) + 1
        ax.plot([p[0] for p in xy], [p[1] for p in xy], marker="osD^v"[k % 5], linestyle=["-", "--", ":", "-."][k % 4],
                color=colour(method), label=label)
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


# ---------------------------------------------------------------- HTML pieces
