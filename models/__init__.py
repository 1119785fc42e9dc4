"""Rigs built from the component library. ``RIGS`` maps the names the
command line accepts (``--rig NAME``) to functions that build them."""
from .paper import PAPER_SIGNALS, PaperRig, paper_rig

RIGS = {"paper": paper_rig}

__all__ = ["PaperRig", "paper_rig", "PAPER_SIGNALS", "RIGS"]
