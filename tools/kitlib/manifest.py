"""A step's manifest, tests/NN_topic/step.json, checked against its current form before anything reads
it (issue 55: a step.json of an older form reached CMake, whose refusal ./kit refresh then hid).

The form (CONTRIBUTING.md, "A step"; tests/fixtures/new_step/tests/06_plane/step.json is the template):

    "title": "A plane"                               required, text
    "summary": "a plane in any orientation: ..."     required, text (README's step table)
    "files": ["plane.cpp"]                           required, a non-empty list of file names (.cpp, .hpp)
    "needs": ["04"]                                  optional, a list of other steps' numbers
    "lecture": "lectures/06-plane.md"                required, a file of the kit
    "functions": [{"name": N, "returns": TYPE, "parameters": [TYPE, ...]}]   required (the judge calls them)
    "contract": {"<topic>.hpp:<function>:<condition>": ["case", ...]}       optional
    "scenes": [{"name", "shadings": ["flat", ...], "about"}]                 optional (a step that draws)
    "runs_without": {"NN": [section, ...]}; "picture_sections": [section, ...]; "picture_note", "image": text
                                                     optional

problems() names each field that is not of that form, as `tests/06_plane/step.json: "functions" entry 0:
...`; check() raises them all at once (./kit course, ./kit refresh). Standard library only.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from raykit.common import ROOT, KitError

REQUIRED = ("title", "summary", "files", "lecture", "functions")
OPTIONAL = ("needs", "contract", "scenes", "runs_without", "picture_sections", "picture_note", "image")
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*$")


def _texts(value) -> bool:
    return isinstance(value, list) and all(isinstance(v, str) and v.strip() for v in value)


def problems(path: Path, numbers: list[str]) -> list[str]:
    """What is not of the current form in the manifest at `path`, each naming its field; [] when none.
    `numbers`: the course's step numbers (a "needs" entry must be one of them)."""
    try:
        where = path.relative_to(ROOT).as_posix()
    except ValueError:
        where = str(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as e:
        return [f"{where}: cannot be read ({e.strerror})"]
    except ValueError as e:
        return [f"{where}: not JSON ({e})"]
    if not isinstance(data, dict):
        return [f"{where}: must be a JSON object {{\"title\": ..., \"files\": [...], ...}}"]
    found = []

    def bad(field: str, why: str) -> None:
        found.append(f"{where}: \"{field}\" {why}")

    for key in REQUIRED:
        if key not in data:
            bad(key, "is missing (the template, tests/fixtures/new_step/tests/06_plane/step.json, shows it)")
    for key in data:
        if key not in REQUIRED + OPTIONAL:
            bad(key, f"is not a field of step.json (the fields: {', '.join(REQUIRED + OPTIONAL)})")
    for key in ("title", "summary", "picture_note", "image"):
        if key in data and not (isinstance(data[key], str) and data[key].strip()):
            bad(key, "must be a non-empty text")
    if "files" in data:
        files = data["files"]
        if not _texts(files) or not files:
            bad("files", "must be a non-empty list of file names, e.g. [\"plane.cpp\"]")
        else:
            kit = path.parents[2]       # the kit (or the template's folder) the manifest is part of
            for f in files:
                if ";" in f or "/" in f or not f.endswith((".cpp", ".hpp", ".h", ".cc")):
                    bad("files", f"entry {f!r} is not a source file's name in the step's folder")
                    continue
                for part in ("steps", "solutions"):     # the stub and the reference, same name (a handout: no solutions/)
                    if (kit / part).is_dir() and not (kit / part / path.parent.name / f).is_file():
                        bad("files", f"entry {f!r}: there is no {part}/{path.parent.name}/{f}")
    if "needs" in data:
        needs = data["needs"]
        own = path.parent.name[:2]
        if not _texts(needs):
            bad("needs", "must be a list of step numbers, e.g. [\"04\"]")
        else:
            for n in needs:
                if n not in numbers or n == own:
                    bad("needs", f"entry {n!r} is not another step's number ({', '.join(numbers)})")
    if "lecture" in data and isinstance(data["lecture"], str):
        if not (ROOT / data["lecture"]).is_file() and not (path.parents[2] / data["lecture"]).is_file():
            bad("lecture", f"names {data['lecture']!r}, which is not a file of the kit")
    elif "lecture" in data:
        bad("lecture", "must be a file's path, e.g. \"lectures/06-plane.md\"")
    if "functions" in data:
        functions = data["functions"]
        if not isinstance(functions, list) or not functions:
            bad("functions", "must be a non-empty list of {\"name\", \"returns\", \"parameters\"}")
        else:
            for i, f in enumerate(functions):
                if not isinstance(f, dict):
                    bad("functions", f"entry {i} ({json.dumps(f)}) is of the older form: now "
                        "{\"name\": ..., \"returns\": TYPE, \"parameters\": [TYPE, ...]}")
                    continue
                name = f.get("name")
                if not (isinstance(name, str) and IDENTIFIER.match(name)):
                    bad("functions", f"entry {i}: \"name\" must be a function's name, not {json.dumps(name)}")
                if not (isinstance(f.get("returns"), str) and f["returns"].strip()):
                    bad("functions", f"entry {i} ({name}): \"returns\" must be a type, e.g. \"std::optional<float>\"")
                if not (isinstance(f.get("parameters"), list) and all(isinstance(p, str) and p.strip()
                                                                       for p in f["parameters"])):
                    bad("functions", f"entry {i} ({name}): \"parameters\" must be a list of types, e.g. [\"const Ray&\"]")
                extra = sorted(set(f) - {"name", "returns", "parameters"})
                if extra:
                    bad("functions", f"entry {i} ({name}): unknown field {', '.join(extra)}")
    if "contract" in data:
        contract = data["contract"]
        if not isinstance(contract, dict):
            bad("contract", "must be {\"<topic>.hpp:<function>:<condition>\": [\"case\", ...]}")
        else:
            for key, cases in contract.items():
                if key.count(":") < 2 or not key.split(":", 1)[0].endswith(".hpp"):
                    bad("contract", f"key {key!r} is not \"<topic>.hpp:<function>:<condition>\"")
                if not _texts(cases):
                    bad("contract", f"{key!r}: must be a list of case names")
    if "scenes" in data:
        scenes = data["scenes"]
        if not isinstance(scenes, list):
            bad("scenes", "must be a list of {\"name\", \"shadings\", \"about\"}")
        else:
            for i, s in enumerate(scenes):
                if not (isinstance(s, dict) and isinstance(s.get("name"), str) and IDENTIFIER.match(s["name"])
                        and _texts(s.get("shadings")) and s["shadings"] and isinstance(s.get("about"), str)):
                    bad("scenes", f"entry {i} is not {{\"name\": NAME, \"shadings\": [\"flat\", ...], \"about\": TEXT}}")
    if "picture_sections" in data and not _texts(data["picture_sections"]):
        bad("picture_sections", "must be a list of the lecture's section headings, e.g. [\"8. Checking the picture\"]")
    if "runs_without" in data:
        runs = data["runs_without"]
        if not (isinstance(runs, dict) and all(_texts(v) for v in runs.values())):
            bad("runs_without", "must be {\"NN\": [the lecture's section headings]}, e.g. {\"04\": [\"5. The camera\"]}")
        else:
            for n in runs:
                if n not in data.get("needs", []):
                    bad("runs_without", f"names step {n!r}, which \"needs\" does not list")
    return found


def manifests(root: Path = ROOT) -> list[Path]:
    return sorted((root / "tests").glob("[0-9][0-9]_*/step.json"))


def check(root: Path = ROOT) -> None:
    """Every step's manifest of the current form, or a KitError naming each field that is not."""
    paths = manifests(root)
    numbers = [p.parent.name[:2] for p in paths]
    found = [line for p in paths for line in problems(p, numbers)]
    if found:
        raise KitError("a step's manifest is not of the current form (CONTRIBUTING.md, \"A step\"):\n  "
                       + "\n  ".join(found))
