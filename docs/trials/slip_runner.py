"""What the trial scripts (trial7_slips.py, trial8_slips.py, trial9_slips.py) share: the correct
student files, the handout's paths, applying one slip and running `./kit check N` per slip.

Each slip is (id, step, file, old, new, what the student did): `old` must occur exactly once in the
correct file, and is replaced by `new`.
"""
import os
import shutil
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
STUDENT = os.path.join(HERE, "trial7_student")

FILES = {
    "unit_sphere.cpp": "steps/01_unit_sphere/unit_sphere.cpp",
    "general_sphere.cpp": "steps/02_general_sphere/general_sphere.cpp",
    "unit_direction.cpp": "steps/03_unit_direction/unit_direction.cpp",
    "rect.cpp": "steps/04_rectangles/rect.cpp",
    "cornell_box.cpp": "steps/05_cornell_box/cornell_box.cpp",
    "render.cpp": "steps/05_cornell_box/render.cpp",
}

# (id, step, file, old, new, what the student did)

def apply(text, old, new):
    if text.count(old) != 1:
        raise SystemExit(f"snippet occurs {text.count(old)} times: {old[:60]!r}")
    return text.replace(old, new)


def slipped(slip):
    sid, step, fname, old, new, _ = slip
    with open(os.path.join(STUDENT, fname + ".txt")) as f:
        text = f.read()
    text = apply(text, old, new)
    return text


def restore(handout):
    for fname, rel in FILES.items():
        shutil.copy(os.path.join(STUDENT, fname + ".txt"), os.path.join(handout, rel))


def run(slips, handout, outdir, only, slipped=slipped):
    os.makedirs(outdir, exist_ok=True)
    for slip in slips:
        sid, step, fname = slip[0], slip[1], slip[2]
        if only and sid not in only:
            continue
        restore(handout)
        with open(os.path.join(handout, FILES[fname]), "w") as f:
            f.write(slipped(slip))
        proc = subprocess.run(["nice", "./kit", "check", str(step)], cwd=handout,
                              capture_output=True, text=True)
        with open(os.path.join(outdir, sid + ".txt"), "w") as f:
            f.write(f"exit {proc.returncode}\n" + proc.stdout + proc.stderr)
        print(sid, "exit", proc.returncode, flush=True)
    restore(handout)


def main(argv, slips, doc, slipped=slipped):
    if argv[:1] == ["--list"]:
        for s in slips:
            print(f"{s[0]:30} step {s[1]}  {s[5]}")
        for s in slips:
            slipped(s)  # every snippet applies
        print(len(slips), "slips")
    elif argv[:1] == ["--run"] and len(argv) >= 3:
        run(slips, argv[1], argv[2], set(argv[3:]), slipped)
    else:
        print(doc)
        return 2
    return 0

