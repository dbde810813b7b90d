"""Material laws: elastic (isotropic or anisotropic), viscoelastic Prony series and their named special cases."""
from .anisotropic import AnisotropicElastic, isotropic_tensor, rotate_stiffness, tensor_to_voigt, voigt_to_tensor
from .base import ComplianceSeries
from .elastic import Elastic
from .fitting import PronyFit, fit_prony
from .viscoelastic import PMMA, KelvinVoigt, Maxwell, StandardLinearSolid, Viscoelastic

__all__ = ["AnisotropicElastic", "ComplianceSeries", "Elastic", "KelvinVoigt", "Maxwell", "PMMA", "PronyFit",
           "StandardLinearSolid", "Viscoelastic", "fit_prony", "isotropic_tensor", "rotate_stiffness",
           "tensor_to_voigt", "voigt_to_tensor"]
