#!/usr/bin/env python
"""Regenerate the paper's Figs. 4-9 and the variant rigs' figures.

    python scripts/reproduce_paper.py [--out DIR] [--figures fig4,fig6]

Same as ``pdbfs reproduce``; the work is done by pdbfs.studies.paper.reproduce.
"""
import sys

from pdbfs.cli import main

if __name__ == "__main__":
    sys.exit(main(["reproduce", *sys.argv[1:]]))
