"""mvtools: a multiview video toolchain compatible with the MPEG reference programs."""

__version__ = "0.1.0"
