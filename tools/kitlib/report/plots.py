"""The report's charts, drawn by matplotlib (Debian's python3-matplotlib) in a child /usr/bin/python3.

The kit's own Python may be another one (pyenv's, a venv) that does not see Debian's packages, and
the student-side commands keep to the standard library: so matplotlib runs in a child process, given
the data as JSON on its standard input, and answers with one SVG per chart (text kept as text, so the
page stays small and searchable). When it cannot run, draw() says why and the page shows a table only.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

PYTHON = "/usr/bin/python3"

_SCRIPT = r'''
import io, json, sys
import matplotlib
matplotlib.use("svg")
import matplotlib.pyplot as plt
plt.rcParams.update({"svg.fonttype": "none", "font.size": 10, "font.family": "DejaVu Sans"})
out = []
for chart in json.load(sys.stdin):
    fig, ax = plt.subplots(figsize=(chart.get("width", 6.4), chart.get("height", 2.8)))
    if chart["kind"] == "hist":
        ax.hist(chart["values"], bins=chart["bins"], color="#1f4e99", edgecolor="white")
        ax.set_xlim(chart["bins"][0], chart["bins"][-1])
        ax.yaxis.get_major_locator().set_params(integer=True)
    else:   # stacked horizontal bars: one bar per label, one segment per series
        left = [0] * len(chart["labels"])
        for name, colour, values in chart["series"]:
            ax.barh(chart["labels"], values, left=left, color=colour, label=name, edgecolor="white")
            left = [a + b for a, b in zip(left, values)]
        ax.invert_yaxis()
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=4, frameon=False, fontsize=9)
        ax.xaxis.get_major_locator().set_params(integer=True)
    ax.set_xlabel(chart["xlabel"])
    ax.set_ylabel(chart.get("ylabel", ""))
    ax.spines[["top", "right"]].set_visible(False)
    fig.tight_layout()
    buf = io.StringIO()
    fig.savefig(buf, format="svg")
    plt.close(fig)
    text = buf.getvalue()
    out.append(text[text.index("<svg"):])
json.dump(out, sys.stdout)
'''


def draw(charts: list[dict]) -> tuple[list[str], str]:
    """(one SVG per chart, "") or ([], why there are none)."""
    if not Path(PYTHON).is_file():
        return [], f"no charts: {PYTHON} is not there (matplotlib runs in Debian's Python)"
    try:
        r = subprocess.run([PYTHON, "-c", _SCRIPT], input=json.dumps(charts), capture_output=True, text=True,
                           timeout=120)
    except subprocess.TimeoutExpired:
        return [], "no charts: matplotlib took over 120 s"
    if r.returncode != 0:
        last = (r.stderr.strip().splitlines() or ["?"])[-1]
        if "No module named" in last:
            return [], "no charts: matplotlib is not installed (sudo apt-get install python3-matplotlib)"
        return [], f"no charts: matplotlib failed ({last[:200]})"
    try:
        svgs = json.loads(r.stdout)
    except ValueError:
        return [], "no charts: matplotlib's answer could not be read"
    return svgs, ""
