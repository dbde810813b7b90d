"""Material laws: elastic (isotropic or anisotropic), viscoelastic Prony series and their named special cases,
Prony fits to relaxation, creep and DMA data, and time-temperature superposition."""
from .anisotropic import AnisotropicElastic, isotropic_tensor, rotate_stiffness, tensor_to_voigt, voigt_to_tensor
from .base import ComplianceSeries
from .elastic import Elastic
from .fitting import PronyFit, fit_prony
from .master_curve import MasterCurve, master_curve
from .temperature import GAS_CONSTANT, WLF, Arrhenius
from .viscoelastic import PMMA, KelvinVoigt, Maxwell, StandardLinearSolid, Viscoelastic

__all__ = ["GAS_CONSTANT", "WLF", "AnisotropicElastic", "Arrhenius", "ComplianceSeries", "Elastic", "KelvinVoigt",
           "MasterCurve", "Maxwell", "PMMA", "PronyFit", "StandardLinearSolid", "Viscoelastic", "fit_prony",
           "isotropic_tensor", "master_curve", "rotate_stiffness", "tensor_to_voigt", "voigt_to_tensor"]
