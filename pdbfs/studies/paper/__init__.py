"""The paper reproduced: Cho & Cha (2010), Figs. 4-9 regenerated from the rig
of pdbfs.models.paper, with the variant rigs' figures and a table of every
curve's peaks (``pdbfs reproduce``).

    cases.py      the paper's parameter studies, horizons, figure names
    figures.py    one function per figure (the paper's axes and legends)
    reproduce.py  reproduce(): run the studies, write PNGs and the table
"""
from .cases import FIGURES
from .reproduce import Reproduction, reproduce

__all__ = ["FIGURES", "Reproduction", "reproduce"]
