"""``rosrun epuck_vrep_compat bag_to_csv run.bag [-o outdir]``: a recorded run as CSV files and
plots, the thesis's Matlab route (section 5, codes 5.3 and 5.4, figures 5.10 to 5.24).

One CSV per topic, exactly as ``rostopic echo -p -b run.bag /topic`` writes it: a header line
``%time,field.a,field.b0,...`` taken from the topic's first message, then one row per message,
time = the bag's receive time in ns, arrays numbered (``field.Posizione_Assoluta0``), arrays of
messages numbered then nested (``field.posizioneOrientamento0.headerGiunto.header.seq``),
``uint8[]`` data left out. The rows are made by rostopic's own CSV functions, so the format
follows the command's by construction (and a test compares the two). A file is named after its
topic with '/' replaced by '_' and without the leading one: ``/Comau_PosOrAss`` ->
``Comau_PosOrAss.csv``. Then the plots of :mod:`epuck_vrep_compat.thesis.bag_plots`.

Exit status: 0 done (topics missing for a plot are only reported), 1 the bag is missing or
cannot be read, 2 bad arguments.
"""
import argparse
import os
import struct
import sys
from typing import Dict, List

import genpy
import rosbag
import rostopic

from epuck_vrep_compat.thesis import bag_plots

BAG_ERRORS = (rosbag.ROSBagException, genpy.DeserializationError, struct.error, OSError)


def csv_name(topic: str) -> str:
    return topic.strip("/").replace("/", "_") + ".csv"


def export_csv(bag: rosbag.Bag, outdir: str) -> Dict[str, int]:
    """Write one CSV per topic of ``bag`` into ``outdir``; {topic: number of rows}."""
    field_filter = rostopic.create_field_filter(echo_nostr=False, echo_noarr=False)
    files, rows = {}, {}
    try:
        for topic, msg, t in bag.read_messages():
            out = files.get(topic)
            if out is None:
                out = files[topic] = open(os.path.join(outdir, csv_name(topic)), "w",
                                          encoding="utf-8")
                out.write("%" + rostopic._str_plot_fields(msg, "field", field_filter) + "\n")
                rows[topic] = 0
            out.write(rostopic._str_plot(msg, current_time=t, field_filter=field_filter) + "\n")
            rows[topic] += 1
    finally:
        for out in files.values():
            out.close()
    return rows


def default_outdir(bag_path: str) -> str:
    stem = bag_path[:-4] if bag_path.endswith(".bag") else bag_path
    return stem + "_export"


def export(bag_path: str, outdir: str) -> List[str]:
    """CSV files and plots of one bag; returns the report's lines. Raises BAG_ERRORS."""
    if not os.path.isfile(bag_path):
        raise OSError(f"no such bag file: {bag_path}")
    os.makedirs(outdir, exist_ok=True)
    with rosbag.Bag(bag_path) as bag:
        rows = export_csv(bag, outdir)
        report = [f"{csv_name(topic)}: {n} rows" for topic, n in sorted(rows.items())]
        report += bag_plots.plot_all(bag, outdir)
    return report


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="bag_to_csv", description="One CSV per topic (as rostopic echo -p -b) and the "
        "thesis's plots: the operator's blob track per camera, each joint's absolute position.")
    parser.add_argument("bag", help="the bag file")
    parser.add_argument("-o", "--outdir", help="output folder (default: <bag>_export)")
    args = parser.parse_args(argv)
    outdir = args.outdir or default_outdir(args.bag)
    try:
        report = export(args.bag, outdir)
    except BAG_ERRORS as e:
        hint = " (try: rosbag reindex)" if isinstance(e, rosbag.ROSBagUnindexedException) else ""
        print(f"bag_to_csv: cannot read {args.bag}: {e}{hint}", file=sys.stderr)
        return 1
    print("\n".join(report))
    print(f"bag_to_csv: wrote {outdir}")
    return 0
