"""./kit mutant: write a mutant (one realistic slip in the reference answer) as a patch.

A mutant is tests/mutants/NN_topic/NAME.patch: one header line, then a unified diff against
solutions/NN_topic/ (git's a/ b/ paths, so `git apply` and `patch -p1` read it too):

    Slip: the window is open (tmin < t < tmax). Caught by: "A hit exactly at tmin counts"
    --- a/solutions/01_unit_sphere/unit_sphere.cpp
    +++ b/solutions/01_unit_sphere/unit_sphere.cpp
    @@ -58,7 +58,7 @@
    ...

The instructor never writes a diff by hand:

    ./kit mutant new 2 sign_flipped     copies the reference to build/mutants/02_.../sign_flipped/
    (edit the copy: make the one slip)
    ./kit mutant save 2 sign_flipped --slip "..."   grades the copy, names the cases that fail
                                                    and writes tests/mutants/02_.../sign_flipped.patch
    ./kit mutant edit 2 sign_flipped    the same copy, rebuilt from an existing patch

The patch holds only the changed lines and a little context, so when a solution changes elsewhere
the mutant still applies and still carries only its slip; when the lines it changes move or
change, it stops applying and `./kit test` names it.
"""

from __future__ import annotations

from pathlib import Path

from raykit import atomic
from raykit.common import BUILD, ROOT, KitError, Step, load_steps, say, select_steps
from raykit.status import FAILED, OK
from raykit.mutants import (MUTANTS, SOLUTIONS, WORK, PatchError, apply_patch, failing_cases, grade_files, read_patch,
                            reference_with, write_patch)
from raykit.mutants import _NAME as NAME


def register(p) -> None:
    p.add_argument("action", choices=["new", "edit", "save"],
                   help="new: copy the reference to edit; edit: the copy of an existing mutant; "
                        "save: write the patch from the copy")
    p.add_argument("number", metavar="N", help="the step number")
    p.add_argument("name", metavar="NAME", help="the slip's name: lower case, digits and _ (e.g. sign_flipped)")
    p.add_argument("--slip", metavar="TEXT", help="save: the slip in one line (kept from the patch when it exists)")
    p.add_argument("--caught-by", metavar="CASE", action="append", default=[],
                   help="save: a case that must catch it (repeatable); without it, the basic cases it fails")


def copy_dir(step: Step, name: str) -> Path:
    return WORK / step.folder / name


def _print_copy(step: Step, name: str, copy: Path, existing: bool) -> None:
    if existing:
        say(f"Mutant {name} of step {step.number} (the reference with its slip) is in {copy.relative_to(ROOT)}/:")
    else:
        say(f"The reference answer of step {step.number} is copied to {copy.relative_to(ROOT)}/:")
    for f in sorted(p.name for p in copy.iterdir() if p.is_file()):
        say(f"  {(copy / f).relative_to(ROOT)}")
    if existing:
        say("Change it, then write the patch again (the slip's line is kept unless you give --slip):")
        say(f"  ./kit mutant save {int(step.number)} {name}")
    else:
        say("Make one realistic slip in it, then write the patch:")
        say(f'  ./kit mutant save {int(step.number)} {name} --slip "what the slip is, in one line"')


def run(args) -> int:
    if not SOLUTIONS.is_dir():
        raise KitError("mutants are written against solutions/, which this copy of the kit does not have")
    if not NAME.match(args.name):
        raise KitError(f"{args.name!r}: a mutant's name is lower case letters, digits and _ (e.g. sign_flipped)")
    [step] = select_steps(load_steps(), [args.number])
    target = MUTANTS / step.folder / f"{args.name}.patch"
    rel_target = target.relative_to(ROOT)

    if args.action == "new":
        if target.exists():
            raise KitError(f"{rel_target} exists already; ./kit mutant edit {int(step.number)} {args.name} "
                           f"gives its copy to change")
        _print_copy(step, args.name, reference_with(step, {}, copy_dir(step, args.name)), False)
        return OK

    if args.action == "edit":
        if not target.exists():
            raise KitError(f"{rel_target} does not exist; ./kit mutant new {int(step.number)} {args.name} starts one")
        try:
            files = apply_patch(read_patch(target, step))
        except PatchError as e:
            raise KitError(f"{rel_target}: {e}", FAILED)
        _print_copy(step, args.name, reference_with(step, files, copy_dir(step, args.name)), True)
        return OK

    return _save(step, args, target)


def _save(step: Step, args, target: Path) -> int:
    copy = copy_dir(step, args.name)
    rel_copy, rel_target = copy.relative_to(ROOT), target.relative_to(ROOT)
    if not copy.is_dir():
        raise KitError(f"there is no copy at {rel_copy}; start with ./kit mutant new {int(step.number)} {args.name}")
    changed = {}
    for ref in sorted((SOLUTIONS / step.folder).iterdir()):
        mine = copy / ref.name
        if ref.is_file() and mine.is_file() and mine.read_text() != ref.read_text():
            changed[ref.name] = mine.read_text()
    if not changed:
        raise KitError(f"{rel_copy} is the reference answer unchanged: make the slip first")
    slip = args.slip
    if slip is None and target.exists():
        try:
            slip = read_patch(target, step).slip
        except PatchError:
            slip = None
    if not slip:
        raise KitError('say what the slip is: --slip "the window is open (tmin < t < tmax)."')

    code, result = grade_files(step, changed, BUILD / "mutant-save")
    failing = failing_cases(result)
    known = [c["name"] for c in result["cases"]] if result else []
    for case in args.caught_by:
        if known and case not in known:
            raise KitError(f"--caught-by {case!r}: step {step.number} has no such case")
    if not failing:
        # Refused, not written: a mutant no case catches is either equivalent (the reference's answers
        # on every case: nothing to catch) or a hole in the suite, and a kept one fails ./kit test
        # until someone knows which (issue 46).
        state = result["state"] if result else f"exit status {code}"
        drop = f"rm -r {rel_copy}" + (f" {rel_target}" if target.exists() else "")
        raise KitError(f"not saved: no basic case catches this slip ({state}). Either it gives the reference's "
                       f"answers on every case (an equivalent mutant: drop it with `{drop}`), or the suite lacks "
                       f"the case that would show it: add one to tests/{step.folder}/ and save again.")
    cases = args.caught_by or failing
    text = write_patch(step, slip, cases, changed)
    target.parent.mkdir(parents=True, exist_ok=True)
    atomic.write(target, text)      # never a half-written patch
    say(f"wrote {rel_target} ({sum(len(h) for h in read_patch(target, step).files.values())} hunk(s))")
    missed = [c for c in cases if c not in failing]
    say(f"caught by {len(failing)} basic case(s); the patch names: " + ", ".join(cases))
    if not args.caught_by and len(cases) > 2:
        say("name only the one or two cases made for this slip: save again with --caught-by CASE (repeatable)")
    if missed:
        say("these named cases do not fail on it: " + ", ".join(missed))
        return FAILED
    return OK
