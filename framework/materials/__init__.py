"""Material laws: elastic, viscoelastic Prony series and their named special cases."""
from .base import ComplianceSeries
from .elastic import Elastic
from .fitting import PronyFit, fit_prony
from .viscoelastic import PMMA, KelvinVoigt, Maxwell, StandardLinearSolid, Viscoelastic

__all__ = ["ComplianceSeries", "Elastic", "KelvinVoigt", "Maxwell", "PMMA", "PronyFit",
           "StandardLinearSolid", "Viscoelastic", "fit_prony"]
