"""The swarm benchmark's records as the README's Markdown table (one row per N).

Ratios compare ours (50 ms step) with Enki's C++ library driven from C++ at the same 50 ms
step; Enki C++ at its own 10 ms step and pyenki are there for reference.
"""


def _find(rows, n, **match):
    for row in rows:
        if row.get("robots") == n and all(row.get(k) == v for k, v in match.items()):
            return row
    return {}


def _num(value, digits=3):
    if value is None:
        return "—"
    if abs(value) >= 100:
        return f"{value:.0f}"
    if abs(value) >= 10:
        return f"{value:.1f}"
    return f"{value:.{digits}g}"


def _kilo(value):
    return "—" if value is None else f"{value / 1000:.1f} k"


def _seconds(value):
    return "—" if value is None else f"{value:.3f}"


def _ratio(ours, peer):
    if ours is None or not peer:
        return "—"
    return f"{ours / peer:.2f}×"


HEADER = ("| N | ours (a) RTF | ours (b) RTF | (b) messages/s (ours / bare roscpp sender) | ours start-up s (topics / "
          "first step) | Enki C++ RTF 10 ms / 50 ms | Enki C++ start-up s | pyenki RTF "
          "(Braitenberg / none) | (a) ÷ Enki C++ 50 ms | (b) ÷ Enki C++ 50 ms | "
          "peak MB ours (a / b) / Enki C++ |\n" + "| --- " * 11 + "|")


def markdown_table(rows):
    """One line per N found in ``rows`` (the JSON records of run_benchmark.py; ours: profile
    ``vrep``, the epuck2_driver rows stay JSON lines)."""
    lines = [HEADER]
    for n in sorted({r["robots"] for r in rows if "robots" in r}):
        a = _find(rows, n, scenario="a_none_subscribed", profile="vrep")
        b = _find(rows, n, scenario="b_all_subscribed", profile="vrep")
        cpp10 = _find(rows, n, peer="enki_cpp", step_s=0.01)
        cpp50 = _find(rows, n, peer="enki_cpp", step_s=0.05)
        py_b = _find(rows, n, peer="enki", controller="braitenberg")
        py_n = _find(rows, n, peer="enki", controller="none")
        msgs = b.get("subscriber_msgs_per_s")
        floor = _find(rows, n, sender="floor_cpp").get("subscriber_msgs_per_s")
        cells = [
            str(n), _num(a.get("rtf")), _num(b.get("rtf")),
            f"{_kilo(msgs)} / {_kilo(floor)}",
            f"{_seconds(a.get('topics_s'))} / {_seconds(a.get('first_step_s'))}",
            f"{_num(cpp10.get('rtf'))} / {_num(cpp50.get('rtf'))}",
            _seconds(cpp50.get("startup_s")),
            f"{_num(py_b.get('rtf'))} / {_num(py_n.get('rtf'))}",
            _ratio(a.get("rtf"), cpp50.get("rtf")), _ratio(b.get("rtf"), cpp50.get("rtf")),
            f"{_num(a.get('peak_rss_mb'))} / {_num(b.get('peak_rss_mb'))} / "
            f"{_num(cpp50.get('peak_rss_mb'))}",
        ]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)
