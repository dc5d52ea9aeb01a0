"""Names and plot styles of the models and quantities in reports: the one table to extend when
a model is added (a model without an entry is shown under its own name, in a default style)."""

from __future__ import annotations

__all__ = [
    "ERROR_LABELS",
    "MODEL_LABELS",
    "MODEL_STYLES",
    "QUANTITY_LABELS",
    "model_label",
    "model_order",
]

MODEL_LABELS = {
    "gw": "original GW",
    "improved_gw": "improved GW",
    "discrete": "discrete (interaction)",
    "discrete_no_interaction": "discrete (no interaction)",
    "persson": "Persson",
    "bem": "BEM (exact)",
}
MODEL_STYLES = {
    "gw": dict(color="tab:blue", linestyle="--"),
    "improved_gw": dict(color="tab:orange", linestyle="-"),
    "discrete": dict(color="tab:green", linestyle="-"),
    "discrete_no_interaction": dict(color="tab:olive", linestyle=":"),
    "persson": dict(color="tab:purple", linestyle="-."),
    "bem": dict(color="black", linestyle="-", linewidth=2.0),
}
QUANTITY_LABELS = {
    "area": "Area = A/L²",
    "load": "Load = W/(E* L²)",
    "separation": "Separation = d/σ",
    "conductance": "Conductance = Cρσ/L²",
    "stiffness": "Stiffness S σ/(E* L²)",
    "contacts": "contacts",
}
ERROR_LABELS = {
    "area": "relative error of area",
    "separation": "error of separation / σ",
    "conductance": "relative error of conductance",
    "stiffness": "relative error of stiffness",
    "contacts": "relative error of contact count",
}


def model_label(model: str) -> str:
    """The report's name of a model (its key when it has none)."""
    return MODEL_LABELS.get(model, model)


def model_rank(model: str) -> int:
    """Position of a model in report order (models without an entry come last)."""
    order = list(MODEL_LABELS)
    return order.index(model) if model in order else len(order)


def model_order(models) -> list[str]:
    """Models in report order: the table's order first, then any others as given."""
    return sorted(models, key=model_rank)
