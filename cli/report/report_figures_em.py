"""The report's figures of model selection and of the EM algorithms (Alhashimi et al., Sensors
2015): Fig. 9-10 the GLR of Algorithm 2, Fig. 13-14 the convergence of EM training and testing,
Fig. 15 the cost of EM testing. Each function draws one PNG into DIR/figures/ and returns a
report_style.Figure, or None when the data do not allow it.
"""

import numpy as np

from report_style import MODE_COLOURS, Figure, legend_right, plt, save


def _family_name(family):
    return "Fourier" if family == "fourier" else family


def _glr_family(data, family):
    g = data.glr
    chosen = g["family"] == family
    ok = chosen & (g["ok"] == 1)
    return g["order"][ok].astype(int), g["glr"][ok], g["bic"][ok], \
        g["held_out_log_likelihood_per_sample"][ok], g["order"][chosen & (g["ok"] != 1)].astype(int)


def _glr(data, directory, family, name, paper):
    if data.glr is None:
        return None
    orders, glr, bic, held_out, failed = _glr_family(data, family)
    if orders.size == 0:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.8))
    ax.plot(orders, glr, marker="o", color="#1f4e9c", label="GLR 2(ℓᵢ − ℓ₀) (Eq. 27-29)")
    best_glr, best_bic, best_held = (orders[np.argmax(glr)], orders[np.argmin(bic)],
                                     orders[np.argmax(held_out)])
    ax.plot([best_glr], [glr.max()], marker="*", markersize=14, color="#d1495b", linestyle="none",
            label=f"largest GLR (Algorithm 2): order {best_glr}")
    ax.axvline(best_bic, color="#2a9d8f", linestyle="--", label=f"smallest BIC: order {best_bic}")
    ax.axvline(best_held, color="#e9a03b", linestyle=":", linewidth=2,
               label=f"best held-out likelihood: order {best_held}")
    equation = "9" if family == "polynomial" else "11"
    ax.set_xlabel(f"{_family_name(family)} order N of H (Eq. {equation})")
    ax.set_ylabel("generalized likelihood ratio")
    ax.set_xticks(orders)
    f0 = data.context.get("glr", {}).get("fourier_f0_per_c")
    suffix = f", f0 = {f0:.3g} /°C" if family == "fourier" and f0 is not None else ""
    ax.set_title(f"Algorithm 2 over {_family_name(family)} bases{suffix}")
    legend_right(ax)
    failures = (f" Training failed for order(s) {', '.join(str(o) for o in failed)}."
                if failed.size else "")
    n = data.context.get("glr", {}).get("training_samples", "the")
    return Figure(paper, save(fig, directory, name),
                  f"The GLR of each {_family_name(family)} basis against the single-Gaussian "
                  f"null (Eq. 28), trained by EM on the {n} training ranges. The GLR grows with "
                  f"every nested order, so the largest is the largest order; BIC and the "
                  f"likelihood of held-out blocks do not, and are the criteria to trust."
                  f"{failures}")


def glr_polynomial(data, directory):
    """Fig. 9: GLR over polynomial orders."""
    return _glr(data, directory, "polynomial", "fig09_glr_polynomial.png",
                "generalized likelihood ratio for the polynomial model")


def glr_fourier(data, directory):
    """Fig. 10: GLR over Fourier orders."""
    return _glr(data, directory, "fourier", "fig10_glr_fourier.png",
                "generalized likelihood ratio for the Fourier model")


def em_training_convergence(data, directory):
    """Fig. 13: the estimates per EM training iteration."""
    c = data.em_convergence
    if c is None or c["iteration"].size == 0:
        return None
    modes = sum(1 for name in c if name.startswith("mean"))
    fig, axes = plt.subplots(3, 1, figsize=(6, 6.5), sharex=True)
    for i in range(modes):
        colour = MODE_COLOURS[i % 4]
        axes[0].plot(c["iteration"], c[f"mean{i + 1}_mm"], color=colour,
                     label=rf"$\hat{{\mu}}_{i + 1}$")
        axes[1].plot(c["iteration"], c[f"weight{i + 1}"], color=colour,
                     label=rf"$\hat{{\pi}}_{i + 1}$")
    axes[2].plot(c["iteration"], c["log_likelihood"], color="k")
    axes[0].set_ylabel("mode offset (mm)")
    axes[1].set_ylabel("mode weight")
    axes[2].set_ylabel("log-likelihood")
    axes[2].set_xlabel("EM training iteration (§5, Eq. 18-19)")
    legend_right(axes[0])
    legend_right(axes[1])
    axes[0].set_title("EM training")
    n = data.context.get("training_samples", "the")
    iterations = data.context.get("em_training_iterations", c["iteration"].size - 1)
    return Figure("convergence of the estimated means during training",
                  save(fig, directory, "fig13_em_training.png"),
                  f"The mode offsets μ̂ᵢ, weights π̂ᵢ and the log-likelihood at each EM training "
                  f"iteration on the {n} training ranges (iteration 0: the start), {iterations} "
                  f"iterations in all.")


def em_testing_convergence(data, directory):
    """Fig. 14: d̂ per EM testing iteration."""
    t = data.em_test_trace
    if t is None or t["iteration"].size == 0:
        return None
    error = t["distance_mm"] - t["true_range_mm"]
    fig, ax = plt.subplots(figsize=(6, 3.6))
    ax.plot(t["iteration"], error, marker="o", color="#1f4e9c", label=r"$\hat{d} - d$")
    ax.axhline(0.0, color="k", linewidth=1, label="true distance")
    ax.set_xlabel("EM testing iteration (§6, Eq. 22-23; 0: the start, the mean of y)")
    ax.set_ylabel(r"$\hat{d} - d$ (mm)")
    ax.set_title("EM testing")
    legend_right(ax)
    n = data.context.get("em_test_trace", {}).get("samples", "the")
    return Figure("convergence of the estimated distance during testing",
                  save(fig, directory, "fig14_em_testing.png"),
                  f"The error of d̂ after each EM testing iteration on the first {n} held-out "
                  f"ranges (the paper's test set had 4000), started as §6 prescribes from the "
                  f"mean of the ranges; it ends {error[-1]:+.3f} mm from the true distance.")


def em_testing_cost(data, directory):
    """Fig. 15: measured time of EM testing against the number of samples."""
    c = data.em_test_cost
    if c is None or c["samples"].size == 0:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.8))
    exponents = []
    for i, order in enumerate(sorted(set(c["fourier_order"].astype(int)))):
        chosen = c["fourier_order"] == order
        k, seconds = c["samples"][chosen], c["seconds"][chosen]
        exponent = np.polyfit(np.log(k), np.log(seconds), 1)[0] if k.size > 1 else float("nan")
        exponents.append(f"order {order}: {exponent:.2f}")
        ax.plot(k, seconds * 1e3, marker="o", color=MODE_COLOURS[i % 4],
                label=f"Fourier order {order} ({2 * order} columns); "
                      f"growth exponent {exponent:.2f}")
    cost = data.context.get("em_test_cost", {})
    steps = cost.get("steps", "")
    left_out = "".join(f" Not timed: {item['basis']}, whose training failed ({item['error']})."
                       for item in cost.get("left_out", []))
    ax.set_xlabel("ranges in the test set K")
    ax.set_ylabel(f"time of {steps} EM test steps (ms)")
    ax.set_title("Cost of EM testing")
    ax.set_ylim(bottom=0)
    legend_right(ax)
    return Figure("computational cost of EM testing for two Fourier orders",
                  save(fig, directory, "fig15_cost.png"),
                  f"Measured wall time (the best of {cost.get('repetitions', 'a few')} runs on "
                  f"this machine) of computing Hθ̂ and {steps} EM test steps on the first K "
                  f"held-out ranges, for each trained Fourier model. The paper found quadratic "
                  f"growth; here each step costs O(K), so the fitted exponent of time ∝ Kᵃ is near "
                  f"1 ({'; '.join(exponents)})"
                  f"{', and the order matters little' if len(exponents) > 1 else ''}.{left_out}")
