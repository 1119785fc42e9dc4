"""python -m pdbfs.cli"""
import sys

from . import main

sys.exit(main())
