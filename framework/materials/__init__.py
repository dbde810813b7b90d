"""Material laws: elastic now, viscoelastic Prony series next."""
from .base import ComplianceSeries
from .elastic import Elastic

__all__ = ["ComplianceSeries", "Elastic"]
