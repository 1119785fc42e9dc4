"""Campaigns: a rig's blows one after another, as a fatigue test runs them,
each a full simulation of the blow from the temperatures the blows before
left, the heat carried between blows by the rig's thermal network.

    setup.py    the arguments checked before any blow is run (Setup, prepare)
    plan.py     the settings of each blow: a Schedule, an operator's rule (HoldPeak)
    heat.py     HeatNetwork: the thermal network alone, linear, its pauses in closed form
    run.py      campaign(): the blows run, saved in chunks and resumed (CampaignStore)
    records.py  Blows: the records so far, as columns; what a rule reads
    result.py   CampaignResult: the table of blows, totals, plot, JSON

May import what pdbfs.studies may, and the studies' sweeps (their Store) and blows.
"""
from .heat import HeatNetwork
from .plan import DROP_HEIGHT, HoldPeak, Schedule, read_schedule, rule_of
from .result import CampaignResult
from .run import CampaignStore, campaign

__all__ = ["campaign", "CampaignResult", "HoldPeak", "Schedule", "HeatNetwork", "rule_of",
           "read_schedule", "DROP_HEIGHT", "CampaignStore"]
