"""Ellipsoidal inhomogeneities (equivalent inclusion method); arrives with THEORY.md sec. 8."""
