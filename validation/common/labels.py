"""Names and plot styles of the models and quantities, as the report and the judge's findings
write them. Model labels and styles come from the registry (:mod:`validation.common.models`); a
model without an entry is shown under its own name, in a default style."""

from __future__ import annotations

from validation.common import models as _models

__all__ = [
    "ERROR_LABELS",
    "MODEL_LABELS",
    "MODEL_STYLES",
    "QUANTITY_LABELS",
    "compared_label",
    "model_label",
    "model_order",
]

#: Model name -> label and plot style: live views of the registry (:mod:`validation.common.models`),
#: so a registered model appears in every table and figure without an edit here.
MODEL_LABELS = _models.labels()
MODEL_STYLES = _models.styles()
QUANTITY_LABELS = {
    "area": "Area = A/L²",
    "load": "Load = W/(E* L²)",
    "separation": "Separation = d/σ (Persson: mean gap ū/σ)",
    "conductance": "Conductance = Cρσ/L²",
    "stiffness": "Stiffness S σ/(E* L²)",
    "contacts": "contacts",
    "leakage": "Leakage = h_eff/σ",
}
ERROR_LABELS = {
    "area": "relative error of area",
    "separation": "error of separation / σ",
    "conductance": "relative error of conductance",
    "stiffness": "relative error of stiffness",
    "contacts": "relative error of contact count",
    "leakage": "ln(h_eff / h_eff of the BEM)",
}
#: What a model's quantity is compared with, by the reference's field: an asperity model's
#: separation is the rigid-plane separation d, Persson's the mean gap ū (docs/theory.md, 7).
FIELD_LABELS = {"separation": "separation d", "mean_gap": "mean gap ū"}


def compared_label(quantity: str, reference_field: str = "") -> str:
    """The name of what is compared: ``separation d`` or ``mean gap ū`` for separations (by
    the reference field the model is compared with), else the quantity's name."""
    return FIELD_LABELS.get(reference_field or quantity, quantity)


def model_label(model: str) -> str:
    """The report's name of a model (its key when it has none); a model at a coarser sampling
    interval (``"gw@2h"``, :mod:`validation.run.sampling`) as ``"original GW at 2h"``."""
    base, at, interval = model.partition("@")
    if at and base in MODEL_LABELS:
        return f"{MODEL_LABELS[base]} at {interval}"
    return MODEL_LABELS.get(model, model)


def model_rank(model: str) -> int:
    """Position of a model in report order (models without an entry come last)."""
    order = list(MODEL_LABELS)
    return order.index(model) if model in order else len(order)


def model_order(models) -> list[str]:
    """Models in report order: the table's order first, then any others as given."""
    return sorted(models, key=model_rank)
