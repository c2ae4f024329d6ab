"""Plots of a campaign's table (rfsitl.campaign.load, Campaign.run) with matplotlib:
a metric's mean over seeds against a parameter, with 95 % confidence
intervals (Student t), one line per value of another parameter."""

import math

import matplotlib.pyplot as plt
from scipy import stats

__all__ = ["mean_ci95", "plot_metric"]


def mean_ci95(values):
    """(mean, half-width of the two-sided 95 % interval, n) of a sample: the
    half-width is t(0.975, n - 1) s / sqrt(n), 0 for a single value."""
    values = [float(v) for v in values]
    n = len(values)
    mean = sum(values) / n
    if n < 2:
        return mean, 0.0, n
    s = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    return mean, float(stats.t.ppf(0.975, n - 1)) * s / math.sqrt(n), n


def plot_metric(df, metric, by, hue=None, ax=None):
    """Plots `metric` against parameter column `by` on `ax` (a new figure's
    when None): one line per value of column `hue` (or one line), the mean
    over the rows (seeds) at each value of `by`, error bars for the 95 %
    interval. Only rows with status "ok" count. Returns the axes."""
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4.5))
    ok = df[(df["status"] == "ok") & df[metric].notna()]
    groups = [(None, ok)] if hue is None else list(ok.groupby(hue, sort=False))
    for label, rows in groups:
        xs, means, cis = [], [], []
        for x, at in sorted(rows.groupby(by), key=lambda item: item[0]):
            mean, ci, _ = mean_ci95(at[metric])
            xs.append(x)
            means.append(mean)
            cis.append(ci)
        ax.errorbar(xs, means, yerr=cis, marker="o", capsize=4,
                    label=metric if label is None else f"{hue}={label}")
    ax.set_xlabel(by)
    ax.set_ylabel(metric)
    ax.set_title(f"{metric}: mean over seeds, 95 % confidence interval")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return ax
