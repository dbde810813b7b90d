"""Visualisation layer: reads framework results, never the other way round.

ParaView export and off-screen pictures arrive with the export issue; the core
(``framework``) does not import this package.
"""
