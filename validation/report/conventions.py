"""How to read a report's numbers: the quantities and their units, the error measures,
separation against mean gap, and how a verdict is reached (on the mean over realizations, per
surface, and on one surface) -- the closing section of every report, in the words of one scan
for a check's report."""

from __future__ import annotations

__all__ = ["ONE_SCAN_QUANTITIES", "conventions"]


#: The quantities of a check's report: one scan in the user's units.
ONE_SCAN_QUANTITIES = (
    "The scene of one scan runs in units of E* and of the scan's length unit: Area = A/A0, the "
    "real contact-area fraction; Load = p/E*, the nominal pressure p over E* (the tables above "
    "give p); separation and mean gap in units of σ, the rms of the scan's summit heights (the "
    "tables above give them in the scan's length unit); the stiffness per unit area K = S/A0 "
    "(N/m³ above). Errors are taken at equal load against the boundary-element (BEM) "
    "reference of this same scan: relative for area and stiffness, in units of σ for "
    "separation and mean gap, and for the leakage (the effective hydraulic aperture h_eff, "
    "leak rate ∝ h_eff³) the logarithm of the ratio, ln(h_eff/h_eff,BEM) = ln(Q/Q_BEM)/3, "
    "equal to the relative error of h_eff to first order. Where exactly one of the two is "
    "sealed (h_eff = 0) that error is undefined: the point fails when the BEM's own error "
    "estimate resolves its state, and is undecided otherwise (docs/theory.md, eq. L7).\n")


def conventions(populations: bool = True, one_scan: bool = False) -> list[str]:
    """How to read the report's numbers: the dimensionless quantities, the error measures,
    separation against mean gap, and how a verdict is reached (on the mean, per surface, and
    on one surface); without ``populations`` (every judged scene has one realization, e.g. a
    check of one scan) the rules over realizations are left out, and with ``one_scan`` (a
    check's report) the quantities are those of one scan in the user's units
    (:data:`ONE_SCAN_QUANTITIES`), not the paper's dimensionless ones."""
    lines = [
        "## How to read the numbers\n",
        "Dimensionless quantities as in the paper: Area = A/L², Load = W/(E* L²), Separation = "
        "d/σ (σ: standard deviation of the summit heights of each realization), Conductance = "
        "Cρσ/L² = −2 ∂Load/∂Separation (C the electrical or thermal contact conductance, ρ "
        "the sum of the two bodies' resistivities: by Barber's analogy Cρ = 2S/E*, S the "
        "normal contact stiffness). Errors are taken at equal load against the "
        "boundary-element (BEM) solution of the same realization: relative for area and "
        "conductance, in units of σ for separation, and for the leakage (the effective "
        "hydraulic aperture h_eff, leak rate ∝ h_eff³) the logarithm of the ratio, "
        "ln(h_eff/h_eff,BEM) = ln(Q/Q_BEM)/3, equal to the relative error of h_eff to first "
        "order. Where exactly one of the two is sealed (h_eff = 0) that error is undefined: "
        "the point fails when the BEM's own error estimate resolves its state, and is "
        "undecided otherwise (docs/theory.md, eq. L7).\n",
        "**Separation and mean gap.** The asperity models (GW, improved GW, discrete) predict "
        "the separation d between the rigid plane and the mean plane of the undeformed rough "
        "surface; they are compared with the BEM's separation d (rows \"separation d\"). "
        "Persson's theory predicts the mean gap ū, the average distance between the rigid "
        "plane and the *deformed* surface; it is compared with the BEM's mean gap (rows "
        "\"mean gap ū\"), also in units of σ. On the non-periodic half-space the two differ by "
        "the mean elastic displacement, which grows with the load; curves.csv lists both for "
        "the BEM (columns separation_d and mean_gap). Persson's conductance is 2S/E* with "
        "S = −dW/dū, compared with the BEM's 2S/E*, S = −dW/dd.\n",
        "**How a verdict is reached.** At each load point the errors over realizations give a "
        "mean and its 95 % confidence interval, mean ± t₀.₉₇₅,ₙ₋₁ · s/√n (Student t, s the "
        "sample standard deviation, n the realizations that converged there). The interval is "
        "widened on both sides by the reference band, the BEM's own error at that point in the "
        "same measure (for the interface of a non-periodic window, solved through its mirror "
        "image, the mirror method's bias is in it: its scatter from surface to surface is in "
        "the realizations' errors already; docs/theory.md, eq. T50). A model **holds** (✔) where the widened interval lies inside ± the "
        "tolerance, the band is at most a quarter of the tolerance and every realization "
        "converged; it **fails** (✘) where the widened interval lies wholly outside; otherwise "
        "the point is **undecided** (?). A validity range is the longest run of ✔. Contact "
        "counts are plotted but not judged: the BEM counts connected contact patches, the "
        "asperity models asperities in contact.\n",
        "**Two readings: on the mean and per surface.** The verdict above is on the *mean* "
        "error over realizations. The verdict **per surface** asks whether the model holds on "
        "single surfaces: it holds per surface where, with the same confidence, at least 90 % "
        "of surfaces have an error within the tolerance (the normal tolerance interval "
        "m ± k₂ s of 90 % content, widened by the band one surface carries, with the mirror "
        "method's whole bound in it, inside ± the tolerance); it "
        "fails per surface where, with that confidence, more than 10 % of surfaces miss "
        '(docs/theory.md, "Per-surface validity"). A scene with a realization budget looks '
        "at its data up to three times, adding realizations while cells are undecided, and "
        "splits the 5 % between the looks (in proportion to their realizations) so that it "
        "holds over all of them "
        '(docs/theory.md, "Sequential realizations").\n',
        "**One surface.** A scene of one realization (one measured scan) is judged on that "
        "surface alone: the BEM solves that very surface, so the only open thing is the BEM's "
        "own band b (the band one surface carries: for a scan's interface, the mirror method's "
        "whole bound in it). A point **holds** where |error| + b ≤ the tolerance, **fails** where "
        "|error| − b > the tolerance, and is undecided only where the band straddles the "
        "tolerance (reason: reference band); no interval over realizations and no per-surface "
        "reading.\n",
    ]
    if one_scan:
        lines[1] = ONE_SCAN_QUANTITIES
        lines = [line.replace("Persson's conductance is 2S/E* with S = −dW/dū, compared with "
                              "the BEM's 2S/E*, S = −dW/dd.", "Persson's stiffness is S = −dW/dū, "
                              "compared with the BEM's S = −dW/dd.") for line in lines]
    if populations:
        return lines
    return [line for line in lines if not line.startswith(("**How a verdict is reached.**",
                                                            "**Two readings"))]
