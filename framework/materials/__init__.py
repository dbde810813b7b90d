"""Material laws: elastic (isotropic or anisotropic), viscoelastic Prony series and their named special cases,
Prony fits to relaxation, creep and DMA data, DMA files read, and time-temperature superposition."""
from .anisotropic import AnisotropicElastic, isotropic_tensor, rotate_stiffness, tensor_to_voigt, voigt_to_tensor
from .base import ComplianceSeries
from .dma import DMASweeps, read_dma
from .elastic import Elastic
from .fitting import PronyFit, fit_prony
from .master_curve import MasterCurve, master_curve
from .temperature import GAS_CONSTANT, WLF, Arrhenius, WLFArrhenius
from .viscoelastic import PMMA, KelvinVoigt, Maxwell, StandardLinearSolid, Viscoelastic

__all__ = ["GAS_CONSTANT", "WLF", "WLFArrhenius", "AnisotropicElastic", "Arrhenius", "ComplianceSeries", "DMASweeps", "Elastic",
           "KelvinVoigt", "MasterCurve", "Maxwell", "PMMA", "PronyFit", "StandardLinearSolid", "Viscoelastic",
           "fit_prony", "isotropic_tensor", "master_curve", "read_dma", "rotate_stiffness", "tensor_to_voigt",
           "voigt_to_tensor"]
