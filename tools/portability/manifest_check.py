#!/usr/bin/env python3
"""Checks cmake/StepManifest.cmake (the regex reader of step.json that replaces CMake 3.19's
string(JSON)) against Python's json module, with the CMake that is installed.

Every tests/NN_topic/step.json must read the same; manifests the regexes cannot read
faithfully (no "files", a number in a list, an empty list) must stop CMake with an error.
Prints one PASS/FAIL line per manifest and exits non-zero on any failure.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = Path(__file__).resolve().parent / "print_manifest.cmake"

# Inputs the reader must refuse, and the words its message must hold.
BAD = {
    "no files": ('{"title": "x", "needs": []}', 'has no "files"'),
    "a number in files": ('{"files": ["a.cpp", 3], "needs": []}', "must be a list of strings"),
    "empty files": ('{"files": [], "needs": []}', '"files" is empty'),
}
# Inputs written differently from the kit's but meaning the same: must read the same.
ODD = {
    "multi-line, no needs": ('{\n  "files": [\n    "a.cpp",\n    "b.cpp"\n  ]\n}', (["a.cpp", "b.cpp"], [])),
    "tight spacing": ('{"needs":["04","02"],"files":["r.cpp"]}', (["r.cpp"], ["04", "02"])),
}


def read(manifest: Path) -> tuple[int, list[str], list[str], str]:
    r = subprocess.run(["cmake", f"-DMANIFEST={manifest}", "-P", str(SCRIPT)],
                       capture_output=True, text=True)
    out = r.stdout + r.stderr
    lists = {}
    for line in out.splitlines():
        for key in ("files", "needs"):
            if line.startswith(f"-- {key}="):
                value = line[len(f"-- {key}="):]
                lists[key] = value.split(";") if value else []
    return r.returncode, lists.get("files", []), lists.get("needs", []), out


def main() -> int:
    passed = failed = 0

    def report(ok: bool, name: str, why: str = "") -> None:
        nonlocal passed, failed
        passed += ok
        failed += not ok
        print(f"{'PASS' if ok else 'FAIL'} step manifest: {name}{'' if ok else ': ' + why}", flush=True)

    for manifest in sorted(ROOT.glob("tests/[0-9][0-9]_*/step.json")):
        data = json.loads(manifest.read_text())
        want = (data["files"], data.get("needs", []))
        code, files, needs, out = read(manifest)
        report(code == 0 and (files, needs) == want, manifest.parent.name,
               f"CMake read files={files} needs={needs}, json has {want}; {out[-300:]}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (text, want) in ODD.items():
            p = Path(tmp) / "step.json"
            p.write_text(text)
            code, files, needs, out = read(p)
            report(code == 0 and (files, needs) == want, name, f"read {files} {needs}: {out[-300:]}")
        for name, (text, words) in BAD.items():
            p = Path(tmp) / "step.json"
            p.write_text(text)
            code, _, _, out = read(p)
            report(code != 0 and words in out, f"refuses {name}", f"exit {code}: {out[-300:]}")
    print(f"manifest check: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
