"""Full elastic half-space contact by FFT boundary elements: the exact reference.

Conventions (shared with the whole project, docs/theory.md): frictionless normal contact of a rough
surface against a rigid plane; pressure positive in compression; gap >= 0; separation d measured
from the rigid plane to the mean plane of the heights in the far field; a point force P at
distance r lowers the surface by P / (pi E* r). Lengths in any consistent unit, pressures in the
unit of E*.
"""

from bem.common.curve import CURVE_QUANTITIES, ContactCurve
from bem.leakage.flow import hydraulic_aperture
from bem.elastic.halfspace import HalfSpace
from bem.interface import InterfaceModel, NominalContactModel
from bem.model import BoundaryElementModel, ContactModel
from bem.contact.path import contact_curve, count_contacts
from bem.contact.solver import ContactSolution, solve_contact
from bem.common.warnings import ConvergenceWarning

__all__ = ["ContactCurve", "CURVE_QUANTITIES", "HalfSpace", "solve_contact", "ContactSolution",
           "contact_curve", "count_contacts", "ConvergenceWarning", "ContactModel",
           "BoundaryElementModel", "InterfaceModel", "NominalContactModel",
           "hydraulic_aperture"]
