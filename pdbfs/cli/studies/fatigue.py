"""pdbfs fatigue: a blow of a rig against a gun firing, by the damage each
does to a breech (rainflow counting of the bore's hoop stress, an S-N curve
and Miner's rule), and the life that follows."""
from __future__ import annotations

import json
import math

from pdbfs.errors import DataError, ParameterError

from ..common import add_rig_options, add_run_options, parse_sets, rig_by_name

FIRING = "gun_firing.csv"


def cmd_fatigue(args):
    """pdbfs fatigue: one blow's damage, one firing's, the blows per firing,
    the drop height of a blow equal to a firing, and the life."""
    from pdbfs.fatigue import campaign_life
    from pdbfs.studies.blows import blow_damage, height_for_damage, height_parameter
    # everything checked before the first run
    breech = breech_of(args)
    cylinder = breech.cylinder
    inner, outer = cylinder.inner_radius, cylinder.outer_radius
    heights = _numbers(args.heights, "--heights", 2, 2, "LO:HI")
    if not 0 < heights[0] < heights[1]:
        raise ParameterError(f"--heights {args.heights}: give 0 < LO < HI (m)")
    if args.blows is not None and args.blows < 1:
        raise ParameterError(f"--blows {args.blows}: a campaign has 1 blow or more")
    firing_path, firing = _firing(args.firing, args.signal)
    rig = rig_by_name(args.rig)
    params = parse_sets(args.set)
    dae = rig.compile()
    drifting = campaign_for_fatigue(args, rig, params, breech)
    d_firing = breech.damage(firing)
    d_blow, res = blow_damage(rig, breech, params, args.t_end, args.backend)
    if d_blow <= 0 or d_firing <= 0:
        raise DataError(f"the {'blow' if d_blow <= 0 else 'firing'} does no damage: its "
                        "stress ranges are all at or below the S-N curve's endurance limit")
    summary = res.summary()
    out = {"rig": dae.name, "params": {**{p.name: p.value for p in dae.params}, **params},
           "breech": {"inner_radius": inner, "outer_radius": outer,
                      "bore_factor": cylinder.bore_factor},
           "sn_curve": {"m": breech.curve.m, "stress_range_ref": breech.curve.stress_range_ref,
                        "cycles_ref": breech.curve.cycles_ref,
                        "endurance_limit": breech.curve.endurance_limit},
           "blow": {"peak_pressure": summary["peak_pressure"], "damage": d_blow,
                    "impacts": summary.get("impact_count", 1)},
           "firing": {"file": firing_path, "peak_pressure": float(firing[1].max()),
                      "damage": d_firing},
           "blows_per_firing": d_firing / d_blow,
           "life_blows": campaign_life([d_blow]), "life_firings": 1.0 / d_firing}
    if height_parameter(dae) is None:
        out["equal_height"] = None
        out["equal_height_note"] = f"rig {dae.name} has no drop height or impact speed"
    else:
        h = height_for_damage(rig, d_firing, breech, tuple(heights), params, args.t_end,
                              args.backend)
        out["equal_height"] = None if h.height is None else \
            {"height": h.height, "parameter": h.parameter, "value": h.value, "damage": h.damage}
        out["equal_height_note"] = h.note
    if drifting is not None:
        out["campaign"] = drifting(d_firing)
    elif args.blows is not None:
        n = args.blows
        out["campaign"] = {"blows": n, "damage": n * d_blow, "firings": n * d_blow / d_firing,
                           "campaigns_to_failure": 1.0 / (n * d_blow)}
    if args.json:
        print(json.dumps(out, allow_nan=False))
    else:
        _report(out)


def breech_of(args):
    """The Breech of --breech and --sn."""
    from pdbfs.fatigue import Breech, SNCurve, ThickCylinder
    inner, outer = _numbers(args.breech, "--breech", 2, 2, "INNER:OUTER")
    return Breech(ThickCylinder(inner, outer),
                  SNCurve(*_numbers(args.sn, "--sn", 3, 4, "M:RANGE:CYCLES[:LIMIT]")))


def add_breech_options(s):
    """--breech and --sn: the breech's wall and its steel's S-N curve."""
    from pdbfs.fatigue import BREECH_CYLINDER as B
    from pdbfs.fatigue import GUN_STEEL_SN as S
    s.add_argument("--breech", default=f"{B.inner_radius:g}:{B.outer_radius:g}",
                   metavar="INNER:OUTER", help="the breech's bore and outer radii, m (default "
                   f"{B.inner_radius:g}:{B.outer_radius:g}: an assumed large-calibre breech)")
    s.add_argument("--sn", default=f"{S.m:g}:{S.stress_range_ref:g}:{S.cycles_ref:g}",
                   metavar="M:RANGE:CYCLES[:LIMIT]",
                   help="the S-N curve of the bore's hoop stress range: N = CYCLES * (RANGE / "
                   "range)^M, no damage at or below LIMIT (Pa) (default "
                   f"{S.m:g}:{S.stress_range_ref:g}:{S.cycles_ref:g}: an engineering estimate "
                   "for a gun steel)")


def campaign_for_fatigue(args, rig, params, breech):
    """pdbfs fatigue's --period (a campaign run) or --campaign DIR (one saved),
    checked before any work: a function of a firing's damage giving the
    campaign's figures, or None for neither."""
    from pdbfs.studies.campaign.run import run, saved
    from pdbfs.studies.campaign.setup import prepare, spec_of_breech
    if args.period is not None and args.blows is None:
        raise ParameterError(f"--period {args.period:g}: give the campaign's --blows too")
    if args.campaign is not None and (args.blows is not None or args.period is not None):
        raise ParameterError(f"--campaign {args.campaign}: the saved campaign has its own blows "
                             "and period; leave --blows and --period out")
    if args.period is not None:
        setup = prepare(rig, args.blows, args.period, params=params, breech=breech,
                        t_blow=args.t_end, backend=args.backend)
        return lambda d_firing: _figures(run(setup, progress=None), d_firing)
    if args.campaign is None:
        return None
    spec, table = saved(args.campaign)
    name = rig.compile().name
    if spec.get("rig") != name:
        raise ParameterError(f"--campaign {args.campaign}: it is a campaign of rig "
                             f"{spec.get('rig')}, not of {name}; give its --rig")
    if spec.get("breech") != spec_of_breech(breech):
        raise ParameterError(f"--campaign {args.campaign}: its damage was reckoned for another "
                             "breech or S-N curve; give its --breech and --sn")
    if len(table) < spec["n_points"]:
        raise ParameterError(f"--campaign {args.campaign}: it holds {len(table)} of its "
                             f"{spec['n_points']} blows; run it to its end first (the same "
                             "pdbfs campaign command resumes it)")
    return lambda d_firing: _figures(table, d_firing, spec["period"], args.campaign)


def _figures(res, d_firing, period=None, folder=None) -> dict:
    """A campaign's figures against one firing (a CampaignResult, or a saved table)."""
    from pdbfs.fatigue import campaign_life
    t = res.table if hasattr(res, "table") else res
    d = t["damage"].to_numpy(dtype=float)
    total = float(d.sum())
    oil = t["oil_temperature"].to_numpy(dtype=float)
    heat = bool(math.isfinite(oil[0]))
    return {"blows": len(t), "period": res.period if hasattr(res, "period") else period,
            "damage": total, "firings": total / d_firing,
            "campaigns_to_failure": 1.0 / total, "life_blows": campaign_life(d),
            "blows_per_firing": d_firing * len(d) / total,
            "peak_pressure_first": float(t["peak_pressure"].iloc[0]),
            "peak_pressure_last": float(t["peak_pressure"].iloc[-1]),
            "oil_temperature_first": float(oil[0]) if heat else None,
            "oil_temperature_last": float(oil[-1]) if heat else None, "folder": folder}


def _firing(path, channel):
    """(the file's name, (t, p)) of the gun firing: the shipped trace by default."""
    from pdbfs.files import example_data
    from pdbfs.studies.fitting.traces import read_trace
    name = path if path is not None else str(example_data(FIRING))
    trace = read_trace(name, "--firing", signal=channel)
    if trace.unit not in ("", "Pa"):
        raise DataError(f"{trace.source}: its column {trace.name!r} is in {trace.unit}, not a "
                        "pressure (Pa, kPa, MPa, bar, psi)")
    return (path if path is not None else FIRING), (trace.t, trace.y)


def _numbers(text, option, least, most, form) -> list[float]:
    """The colon-separated numbers of ``option``, ``least`` to ``most`` of them."""
    parts = str(text).split(":")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if not least <= len(values) <= most or not all(math.isfinite(v) for v in values):
        raise ParameterError(f"{option} {text}: expected {form}, numbers separated by colons")
    return values


def _report(out):
    """The report as a table."""
    b, c, bl, f = out["breech"], out["sn_curve"], out["blow"], out["firing"]
    print(f"rig {out['rig']}: one blow against one gun firing ({f['file']})")
    print(f"  breech: bore radius {b['inner_radius']:g} m, outer radius {b['outer_radius']:g} m "
          f"(bore hoop stress {b['bore_factor']:.4g} x pressure)")
    limit = f", endurance limit {c['endurance_limit']:.4g} Pa" if c["endurance_limit"] else ""
    print(f"  S-N curve: m = {c['m']:g}, {c['cycles_ref']:.4g} cycles at a hoop stress range "
          f"of {c['stress_range_ref']:.4g} Pa{limit}")
    blow = "one blow" + (f" ({bl['impacts']} impacts)" if bl["impacts"] > 1 else "")
    print(f"  {blow:<34} peak {bl['peak_pressure']:>12.6g} Pa   damage {bl['damage']:.6g}")
    print(f"  {'one firing':<34} peak {f['peak_pressure']:>12.6g} Pa   damage {f['damage']:.6g}")
    print(f"  {'blows that stand for one firing':<34} {out['blows_per_firing']:.6g}")
    h = out["equal_height"]
    if h is None:
        print(f"  {'drop height of a blow = a firing':<34} n/a: {out['equal_height_note']}")
    else:
        speed = f" ({h['parameter']} = {h['value']:.6g} m/s)" if h["parameter"].endswith(".v0") \
            else ""
        print(f"  {'drop height of a blow = a firing':<34} {h['height']:.6g} m{speed}")
    print(f"  {'predicted life':<34} {out['life_blows']:.6g} blows = "
          f"{out['life_firings']:.6g} firings")
    camp = out.get("campaign")
    if camp:
        every = f", one every {camp['period']:g} s" if camp.get("period") else ""
        print(f"  campaign of {camp['blows']} blows{every}: damage {camp['damage']:.6g} = "
              f"{camp['firings']:.6g} firings; {camp['campaigns_to_failure']:.6g} such "
              "campaigns to failure")
    if camp and camp.get("period"):
        heat = "" if camp["oil_temperature_first"] is None else \
            (f"the oil from {camp['oil_temperature_first']:.5g} to "
             f"{camp['oil_temperature_last']:.5g} K, ")
        print(f"    {heat}the peak from {camp['peak_pressure_first']:.6g} to "
              f"{camp['peak_pressure_last']:.6g} Pa; {camp['blows_per_firing']:.6g} blows per "
              f"firing; predicted life {camp['life_blows']:.6g} blows")


def add_parsers(sub):
    """Add the ``fatigue`` command to the subparsers ``sub``."""
    s = sub.add_parser("fatigue", help="the damage a blow does to a breech against a gun "
                       "firing's: blows per firing, the drop height of a blow equal to a firing, "
                       "the breech's life")
    add_rig_options(s)
    add_run_options(s, n_out=False, method=False, rtol=False)
    add_breech_options(s)
    s.add_argument("--firing", default=None, metavar="FILE",
                   help="the chamber pressure of one gun firing: a CSV (time, pressure), or a "
                   "TDMS or MDF file (pdbfs[lab]) (default: the synthetic firing pdbfs ships)")
    s.add_argument("--signal", default=None, metavar="NAME",
                   help="the column or channel of --firing holding the pressure (default: its "
                   "only one)")
    s.add_argument("--heights", default="0.01:5", metavar="LO:HI",
                   help="the drop heights searched for a blow equal to a firing, m "
                   "(default 0.01:5)")
    s.add_argument("--blows", type=int, default=None, metavar="N",
                   help="a campaign of N such blows: its damage, the firings it stands for, "
                   "and the campaigns to failure")
    s.add_argument("--period", type=float, default=None, metavar="S",
                   help="with --blows: run the campaign, one blow every S seconds, each from "
                   "the temperatures the blows before left (the drift of a rig with heat), "
                   "and give its predicted life")
    s.add_argument("--campaign", default=None, metavar="DIR",
                   help="the campaign saved in DIR (pdbfs campaign --out DIR) instead of N "
                   "blows alike: its damage, its blows per firing and its predicted life")
    s.add_argument("--json", action="store_true", help="print the results as one JSON object")
    s.set_defaults(func=cmd_fatigue)
