"""Fatigue of a breech from pressure histories: a rig's blow, a campaign of
blows or a measured gun firing, each taken to a damage and a life.

pressure -> the bore's hoop stress (Lamé) -> rainflow cycles (ASTM E1049-85)
-> an S-N curve and Miner's sum; and beside it the growth of a crack at the
bore by Paris' law, with the pressure on its faces.

    counting      rainflow(): the cycles of a history (an array, a pair (t, y),
                  a trace, or a Result, whose reversals are located on its solution)
    sn            SNCurve: Basquin's S-N curve with an endurance limit; Miner's damage
    cylinder      ThickCylinder: Lamé's stresses in a thick-walled cylinder
    crack         ParisLaw, crack_growth_cycles(): a radial crack at the bore
    breech        Breech: a cylinder and its S-N curve, a history's damage per blow;
                  campaign_life(): the blows a campaign's damages allow
    checks        the numbers of these classes checked, each named when wrong

Pure numerics on pressure histories: a Result is taken duck-typed (its
times, its variables by name, its located peaks), so nothing here imports
the simulation.

May import: pdbfs.errors and pdbfs.files. pdbfs.studies, pdbfs.cli and
pdbfs.app import from here.
"""
from .breech import BREECH_CYLINDER, Breech, campaign_life
from .counting import history_values, rainflow
from .crack import GUN_STEEL_PARIS, ParisLaw, crack_growth_cycles, equivalent_range
from .cylinder import ThickCylinder
from .sn import GUN_STEEL_SN, SNCurve

__all__ = ["rainflow", "history_values", "SNCurve", "GUN_STEEL_SN", "ThickCylinder",
           "BREECH_CYLINDER", "ParisLaw", "GUN_STEEL_PARIS", "crack_growth_cycles",
           "equivalent_range", "Breech", "campaign_life"]
