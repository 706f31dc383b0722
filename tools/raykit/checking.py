"""Checking one build: compile the judge and the student's answers program, run the cases.

The judge (a step's test program) never loads the student's code: it calls each
step function in a child process, the answers program, which it starts itself
(in a sandbox when the folder graded is not the student's own; see sandbox/),
and judges the answers it gets back. Nothing the student's code prints or writes
reaches the verdicts. This module builds a step's judge and answers program, has
its cases run (runcases.py: the judge run with a time limit per case as a backstop,
its verdicts read) and says what state the step is in (the cases and results:
cases.py); it keeps the untouched steps' recorded cases, a grading's verdicts by
content, and check_steps, which checks a build's steps.

One scale: every case of every step counts, whatever state the step is in. A step
whose code is missing or does not compile has all its cases failed; a step that
needs another is graded, where solutions/ is present, on a stand-in for that other
step scripted from the reference's program (tests/support/standin.hpp), so one slip
costs one step and no reference code is in the student's process.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
from contextlib import suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from . import atomic, heldtmp, runfolders, slips
from . import course as course_file
from . import faults
from . import includes
from . import waits
from . import bundle
from .cases import SCORED_TIERS, Case, StepResult
from .common import BUILD, ROOT, InOrder, Step, load_steps, map_in_threads, prerequisites
from .build import Build, detect_undefined, shown_text
from .objcache import ObjectCache
from .runcases import list_cases, record_reference_time, rerun_timeouts, rerun_unsent_kills, run_cases, step_budget
from .sandbox import NONE_OWN, SANDBOX_FAILED, Isolation, Scratch
from .secret import hidden_seed
from .status import GRADER_ERROR, NOT_GRADED, DONE, MISSING, NOT_STARTED, NO_COMPILE, PARTIAL, PASS, TIMED_OUT, WAITING


def submission_seed(build: Build, step: Step) -> str:
    """The hidden cases' seed: from the instructor's secret, the submission's identity and the step's
    files (secret.py), so no student can know or steer it and a re-grade meets the same inputs."""
    if not hidden_cases_here():
        return ""               # a handout: no hidden cases, no secret
    paths = [build.steps_dir / step.folder / f for f in step.files]
    return hidden_seed(step.folder, [p.read_bytes() if p.is_file() else None for p in paths], build.identity)


def not_graded(step: Step, reason: str, cases: list[Case] | None = None, detail: str = "") -> StepResult:
    """A step the grader failed: every case without a verdict (GRADER_ERROR), its recorded ones when
    the judge could not list them, so the step keeps its points' maximum and loses none of them."""
    cases = cases if cases else (recorded_cases(step) or [])
    return StepResult(step, NOT_GRADED, _all(cases, GRADER_ERROR, f"not graded: {reason}"),
                      detail=detail or f"not graded, the grader's fault, not the student's: {reason}",
                      reason=reason)


def _all(cases: list[Case], status: str, message: str) -> list[Case]:
    for c in cases:
        c.status, c.messages = status, [message]
    return cases


@dataclass
class Built:
    """What building a step's answers program gave; the judge is the bundle's."""
    judge: Path | None          # the bundle's judge (None: the kit's side did not build)
    answers_ok: bool
    output: str                 # the compiler's and the linker's output (the errors, if any)
    missing: list[str] = field(default_factory=list)    # the step's files not there when it was built


def build_step(build: Build, step: Step, kit: bundle.Bundle, isolation: Isolation,
               progress: Callable[[int, int], None] | None = None) -> Built:
    """Compiles the student's files of `step` (and of the steps of theirs it links: a handout's, or one
    the kit has no stand-in for) in parallel, and links them with the bundle's objects for the step,
    each inside the boundary (Isolation.tool), into `build`'s folder. Nothing of the kit's is built
    here (bundle.py), and no build tool is run."""
    judge = kit.judge(step)
    missing = [f for f in step.files if not (build.steps_dir / step.folder / f).is_file()]
    if missing:
        return Built(judge, False, "", missing)
    own_needs = kit.own_needs(step)
    by_folder = {s.folder: s for s in load_steps()} if own_needs else {}
    sources: list[tuple[str, str]] = [(step.folder, f) for f in step.files]
    for folder in own_needs:
        need = by_folder.get(folder)
        absent = [f for f in need.files if not (build.steps_dir / folder / f).is_file()] if need else ["?"]
        if absent:
            return Built(judge, False, f"{folder}/{absent[0]} is missing: step {folder[:2]} is needed first\n")
        sources += [(folder, f) for f in need.files]
    use = "grade" if build.boundary else "check"
    objects_dir = build.binary_dir / "objects"
    commands = [kit.compile_command(use, build.steps_dir / folder / f, objects_dir / folder / (f + ".o"))
                for folder, f in sources]
    total = len(commands) + 1
    done = [0]

    def compile_one(argv: list[str]) -> tuple[int, str]:
        result = isolation.tool("compile", argv, build.binary_dir, ObjectCache)
        done[0] += 1
        if progress:
            progress(done[0], total)
        return result

    compiled = map_in_threads(compile_one, commands, os.cpu_count() or 1)
    texts = [text for _, text in compiled]
    ok = all(status == 0 for status, _ in compiled)
    if ok:
        answers = build.binary_dir / f"answers_step{step.number}"
        link = kit.link_command([c[c.index("-o") + 1] for c in commands] + kit.kit_objects(step), answers)
        key, stamp = _link_key(link), answers.with_name(answers.name + ".inputs")
        if key is None or not answers.is_file() or not stamp.is_file() or stamp.read_text() != key:
            stamp.unlink(missing_ok=True)
            status, text = isolation.tool("link", link, build.binary_dir)
            texts.append(text)
            ok = status == 0
            if ok and key is not None:
                atomic.write(stamp, key)
        if progress:
            progress(total, total)
    return Built(judge, ok, shown_text(build, "".join(texts)))


def _link_key(link: list[str]) -> str | None:
    """A link's command and the content of every object it reads, as recorded beside the answers
    program it made (a check of unchanged files links nothing again); None when an input is unreadable."""
    h = hashlib.sha256("\0".join(link).encode())
    try:
        for arg in link:
            if arg.endswith(".o"):
                h.update(Path(arg).read_bytes())
    except OSError:
        return None
    return h.hexdigest()


def judge_step(build: Build, step: Step, built: Built, results: dict[str, StepResult],
               isolation: Isolation, tiers: set[str] | None = None) -> StepResult:
    """Runs a built step's cases and says what state the step is in; only those of `tiers` when given
    (the fairness table re-runs the hidden cases alone on each draw)."""
    # A full disk is not read here from the build's words (a compiler quotes the student's source): the
    # boundary raises faults.MachineFault from the kit's own errno or measure (sandbox/runner.py).
    if built.judge is None:
        why = "the kit's test program does not build (a kit bug)"
        return not_graded(step, why, detail=why + ":\n" + built.output)
    judge = built.judge
    try:
        cases = [c for c in list_cases(judge) if tiers is None or c.tier in tiers]
    except (RuntimeError, subprocess.TimeoutExpired, OSError) as e:
        return not_graded(step, f"the test program could not list its cases: {e}")
    if built.missing:
        detail = f"{step.folder}/{built.missing[0]} is missing"
        return StepResult(step, MISSING, _all(cases, MISSING, detail), detail=detail)
    if not build.reference_needs:
        # No reference here (a student's handout): the step runs on the student's own
        # earlier steps, so the cases that call them wait until they are done (waits.py).
        need = waits.waits_whole(step, results)
        if need:
            return StepResult(step, WAITING, _all(cases, WAITING, f"needs step {need} done first"), detail=need)
    if not built.answers_ok and SANDBOX_FAILED in built.output:
        line = next(l for l in built.output.splitlines() if SANDBOX_FAILED in l)
        return StepResult(step, NOT_GRADED, _all(cases, GRADER_ERROR, line), isolation=isolation.description,
                          detail="not graded, the grader's fault, not the student's: " + line.removeprefix("raykit: "),
                          reason=line.removeprefix("raykit: "))
    # A standard header the student's files use without including it (includes.py): said in the same
    # words whether the file compiles here (a warning under the step) or not (the error's first line).
    found = includes.step_findings(build.steps_dir, step.folder, step.files, ROOT / "include")
    if not built.answers_ok:
        first = found[0] if found else next((l for l in built.output.splitlines() if "error" in l), "")
        return StepResult(step, NO_COMPILE, _all(cases, NO_COMPILE, "does not compile: " + first.strip()),
                          detail="\n".join(found + [built.output]), includes=found)
    seed = submission_seed(build, step)
    # The step's budget (runcases.py, "Budgets"): its ledger in a folder of the grader's, which the
    # sandboxed code cannot reach, shared by every run of the judge, the cases run again too.
    with heldtmp.held("raykit-ledger-") as ledger_dir:
        scratch = Scratch(isolation, build.binary_dir / f"answers_step{step.number}")
        try:
            budget = step_budget(step, ledger_dir / "ledger")
            env = dict(scratch.env(), RAYKIT_SEED=seed, **budget.env())
            if not isolation.sandboxed:
                env["RAYKIT_ANSWERS"] = str(build.binary_dir / f"answers_step{step.number}")
            run_cases(judge, cases, env, *course_file.load().case_limits(), budget=budget)   # course.json time_limits
            rerun_timeouts(judge, cases, env, scratch.between_runs, looped=budget.spent()["looped"])
            rerun_unsent_kills(judge, cases, env, scratch.between_runs)
            record_reference_time(build, step, budget, cases)
            spent = budget.spent()
            cost = {"cpu": round(spent["cpu"], 3), "wait": round(spent["wait"], 3), "calls": spent["calls"],
                    "cpu_budget": budget.cpu, "wait_budget": budget.wait,
                    **({"reference_cpu": budget.reference["cpu"]} if budget.reference else {})}
        finally:
            scratch.close()
    failed_sandbox = [c for c in cases if c.status == GRADER_ERROR]
    if failed_sandbox:      # the sandbox, the judge, the disk: no verdict for the step (faults.py)
        first = failed_sandbox[0].messages[0] if failed_sandbox[0].messages else "no verdict"
        fault = (failed_sandbox[0].incident or {}).get("fault")
        reason = f"{fault} in {len(failed_sandbox)} of {len(cases)} cases" if fault else first
        return StepResult(step, NOT_GRADED, cases, isolation=isolation.description, reason=reason,
                          detail=f"not graded, the grader's fault, not the student's ({len(failed_sandbox)} of "
                                 f"{len(cases)} cases without a verdict): {first}")
    scored = [c for c in cases if c.tier == "basic"]
    if scored and all(c.status == NOT_STARTED for c in cases if c.tier != "hidden"):
        state = NOT_STARTED
    elif all(c.status == PASS for c in cases if c.tier in SCORED_TIERS):
        state = DONE
    else:
        state = PARTIAL
    if not build.reference_needs:
        state = waits.wait_on_needs(step, cases, results, state)
    slip = slips.match(step, cases)
    result = StepResult(step, state, cases, detail=",".join(waits.pending(step, results)) if state == WAITING else "",
                        isolation=isolation.description, seed=seed if any(c.tier == "hidden" for c in cases) else "",
                        cost=cost, includes=found, slip=slip)
    slips.say(result)
    return result


# --- untouched steps: no build ---------------------------------------------------------------
# A step whose files are byte for byte the shipped stubs is "not started" without a compile: its
# state comes from the content. tests/stubs.json records the stubs' hashes, tests/NN_topic/cases.json
# each judge's visible cases and tests/hidden/cases.json the hidden ones (not in a handout), so that
# such a step still has its cases and its points on the one scale. `./kit check --record` writes
# them; the self-test fails when they are stale.
STUBS_FILE = ROOT / "tests" / "stubs.json"
HIDDEN_CASES_FILE = ROOT / "tests" / "hidden" / "cases.json"


def file_hash(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def untouched(build: Build, step: Step) -> bool:
    try:
        stubs = json.loads(STUBS_FILE.read_text())
    except (OSError, ValueError):
        return False
    for f in step.files:
        p = build.steps_dir / step.folder / f
        key = f"{step.folder}/{f}"
        if key not in stubs or not p.is_file() or file_hash(p) != stubs[key]:
            return False
    return True


def hidden_cases_here() -> bool:
    """Whether the judges hold hidden cases: the reference and tests/hidden/ are here."""
    return (ROOT / "solutions").is_dir() and (ROOT / "tests" / "hidden").is_dir()


def recorded_cases(step: Step) -> list[Case] | None:
    """The cases the step's judge lists, as recorded; None when there is no record."""
    try:
        visible = json.loads((ROOT / "tests" / step.folder / "cases.json").read_text())
        hidden = json.loads(HIDDEN_CASES_FILE.read_text()).get(step.number, []) if hidden_cases_here() else []
    except (OSError, ValueError):
        return None
    return [Case(c["name"], c["tier"], c.get("lecture", "")) for c in visible + hidden]


def untouched_result(step: Step, cases: list[Case]) -> StepResult:
    """Not started, whatever the steps it needs: nothing of it is written yet."""
    for c in cases:
        c.status, c.messages = NOT_STARTED, ["not started: the step's files are the shipped stubs "
                                             "(each function is still not_implemented_yet)"]
    return StepResult(step, NOT_STARTED, cases)


def record(kit: bundle.Bundle, steps: list[Step], all_steps: list[Step] | None = None) -> list[Path]:
    """Writes tests/stubs.json from steps/ (every step of `all_steps`, default `steps`) and the case
    lists of `steps` from the bundle's judges (`kit` must have the hidden cases, i.e. solutions/
    present); the hidden case lists of the other steps are kept. Returns the files written."""
    stubs = {f"{s.folder}/{f}": file_hash(ROOT / "steps" / s.folder / f) for s in all_steps or steps
             for f in s.files}
    written = [STUBS_FILE]
    STUBS_FILE.write_text(json.dumps(stubs, indent=1, sort_keys=True) + "\n")
    known = {s.number for s in all_steps or steps}
    try:
        kept = json.loads(HIDDEN_CASES_FILE.read_text()) if all_steps else {}
    except (OSError, ValueError):
        kept = {}
    hidden: dict[str, list] = {n: v for n, v in kept.items() if n in known}
    for s in steps:
        cases = list_cases(kit.judge(s))
        entry = lambda c: {"name": c.name, "tier": c.tier, "lecture": c.lecture}   # noqa: E731
        target = ROOT / "tests" / s.folder / "cases.json"
        target.write_text(json.dumps([entry(c) for c in cases if c.tier != "hidden"], indent=1) + "\n")
        written.append(target)
        hidden[s.number] = [entry(c) for c in cases if c.tier == "hidden"]
    HIDDEN_CASES_FILE.write_text(json.dumps(hidden, indent=1, sort_keys=True) + "\n")
    return written + [HIDDEN_CASES_FILE]


# --- one verdict per content within a grading --------------------------------------------------
# `./kit grade` names a folder of its own (RAYKIT_VERDICTS_DIR, made afresh for each run and
# removed after it) where each submission's check keeps its steps' results by content: a step
# whose files are byte for byte another submission's (a copy of the solutions, the same slip) was
# already compiled, run and judged, with the same hidden cases (their seed is a hash of the
# files), so it takes that verdict without a build. The key holds everything else a result
# depends on that can differ inside one grading: the isolation's kind, and, where there is no
# reference (a handout), the files of the steps it needs. Only the grader writes there (build/ is
# hidden from graded code); a result with a case that timed out or a sandbox that failed is never
# kept, so each copy gets its own chance at it.
VERDICTS_ENV = "RAYKIT_VERDICTS_DIR"


def verdict_key(build: Build, step: Step, all_steps: list[Step], isolation: Isolation) -> str:
    h = hashlib.sha256(f"raykit-verdict-2\0{isolation.mode.split(':')[0]}\0{build.reference_needs}\0".encode())
    h.update(build.identity.encode("utf-8", "surrogateescape") + b"\0")   # the hidden cases' draw
    for s in [step] + ([] if build.reference_needs else prerequisites(step, all_steps)):
        for f in s.files:
            p = build.steps_dir / s.folder / f
            h.update(f"{s.folder}/{f}\0".encode() + (p.read_bytes() if p.is_file() else b"\0missing") + b"\0")
    return h.hexdigest()


class Verdicts:
    """The grading's verdicts by content (see above); `here()` is None outside a grading."""

    SHOWN = "@SHOWN@"       # where the submission's own path stood in the text
    CASE_FIELDS = ("name", "tier", "lecture", "status", "messages", "output", "output_bytes", "figure", "runs",
                   "rerun", "incident")

    def __init__(self, folder: Path, build: Build, all_steps: list[Step], isolation: Isolation):
        self.folder, self.build, self.all_steps, self.isolation = folder, build, all_steps, isolation
        self.paths: dict[str, Path] = {}    # by step: the files are read once, before the build

    @classmethod
    def here(cls, build: Build, all_steps: list[Step], isolation: Isolation) -> "Verdicts | None":
        named = os.environ.get(VERDICTS_ENV)
        if not named or not build.boundary or not Path(named).is_dir():
            return None
        return cls(Path(named), build, all_steps, isolation)

    def _path(self, step: Step) -> Path:
        if step.number not in self.paths:
            self.paths[step.number] = self.folder / f"{verdict_key(self.build, step, self.all_steps, self.isolation)}.json"
        return self.paths[step.number]

    def load(self, step: Step) -> StepResult | None:
        try:
            d = json.loads(self._path(step).read_text())
        except (OSError, ValueError):
            return None
        shown = str(self.build.shown_dir)
        cases = [Case(**{k: c[k] for k in self.CASE_FIELDS if k in c}) for c in d["cases"]]
        return StepResult(step, d["state"], cases, detail=d["detail"].replace(self.SHOWN, shown),
                          isolation=self.isolation.description, seed=d["seed"], includes=d.get("includes", []),
                          slip=d.get("slip"), reason=d.get("reason", ""))

    KEEP_TIMEOUTS = False   # a grading's copies each get their own chance at a case that timed out

    def store(self, result: StepResult, everything: bool = False) -> None:
        """Keeps `result` for its content; not one the grader failed (not graded, a sandbox that could
        not start), unless `everything`."""
        if not everything and (result.state == NOT_GRADED or any(c.status == GRADER_ERROR for c in result.cases) or
                               (not self.KEEP_TIMEOUTS and any(c.status == TIMED_OUT for c in result.cases))):
            return
        shown = str(self.build.shown_dir)
        data = {"state": result.state, "detail": result.detail.replace(shown, self.SHOWN), "seed": result.seed,
                "includes": result.includes, "slip": result.slip, "reason": result.reason,
                "cases": [{k: getattr(c, k) for k in self.CASE_FIELDS} for c in result.cases]}
        with suppress(OSError):
            atomic.write(self._path(result.step), json.dumps(data))


class LastCheck(Verdicts):
    """The student's last `./kit check`, step by step, by content (build/last-check/): `./kit hint` takes
    its first failing case from there instead of running the step's cases again while the step's files
    (and those of the steps it needs), the isolation and the judge program are the same as then."""

    FOLDER = BUILD / "last-check"
    KEEP_TIMEOUTS = True    # what the student was shown, a loop included

    def __init__(self, build: Build, all_steps: list[Step], isolation: Isolation):
        super().__init__(self.FOLDER, build, all_steps, isolation)

    def _path(self, step: Step) -> Path:
        if step.number not in self.paths:
            # The judge that gave the verdict: the bundle's (the build folder holds none since the
            # bundle), so a kit whose judge changed since (a new case, a new message) runs the cases
            # again instead of showing an older judge's first failing case.
            found = bundle.find(detect_undefined())
            try:
                st = (found.judge(step) if found is not None else self.build.exe(step)).stat()
                judge = f"{st.st_size}-{st.st_mtime_ns}"
            except (OSError, KeyError):
                judge = "no judge"
            key = verdict_key(self.build, step, self.all_steps, self.isolation)
            self.paths[step.number] = self.folder / f"{key[:32]}-{hashlib.sha256(judge.encode()).hexdigest()[:16]}.json"
        return self.paths[step.number]

    def keep(self, results: list[StepResult]) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        def age(p: Path) -> float:
            try:
                return p.stat().st_mtime
            except OSError:             # removed a moment ago by another check's pruning
                return 0.0
        for old in sorted(self.folder.glob("*.json"), key=age)[:-64]:
            old.unlink(missing_ok=True)       # the last few dozen checks are plenty
        for r in results:
            self.store(r)


class OneResult(Verdicts):
    """One step's result in a file of its own (./kit watch's check, run in a child process)."""

    def __init__(self, path: Path, build: Build, all_steps: list[Step]):
        super().__init__(path.parent, build, all_steps, NONE_OWN)
        self.path = path

    def _path(self, step: Step) -> Path:
        return self.path


class Progress:
    """What check_steps says while it works; the default says nothing (scoreboard.LiveProgress
    shows it on a terminal)."""

    def phase(self, text: str) -> None: ...
    def building(self, step: Step, done: int, total: int) -> None: ...
    def result(self, result: StepResult) -> None: ...


def check_steps(build: Build, steps: list[Step], all_steps: list[Step], isolation: Isolation = NONE_OWN,
                progress: Progress | None = None) -> list[StepResult]:
    """Checks `steps`; without a reference, first the steps they need (quietly, to know whether they
    are done). A build folder that is not a run's own (build/student, build/SLOT) is held for the
    check (runfolders.using): a second check of it waits, told for whom, rather than mix the two."""
    if runfolders.RUNS in build.binary_dir.parents:
        return _check_steps(build, steps, all_steps, isolation, progress)
    with runfolders.using(build.binary_dir, "a check"):
        return _check_steps(build, steps, all_steps, isolation, progress)


def _check_steps(build: Build, steps: list[Step], all_steps: list[Step], isolation: Isolation,
                 progress: Progress | None) -> list[StepResult]:
    """check_steps, in a build folder that is this run's alone.

    Pipelined: while one step's cases run (in a worker thread, in course order), the next step is
    built, so the first verdict comes after one step's build and the others follow as they build.
    """
    progress = progress or Progress()
    wanted = {s.number for s in steps}
    needed = set() if build.reference_needs else {p.number for s in steps for p in prerequisites(s, all_steps)}
    order = [s for s in all_steps if s.number in wanted or s.number in needed]
    quick = {s.number: cases for s in order if untouched(build, s)
             for cases in [recorded_cases(s)] if cases is not None}
    verdicts = Verdicts.here(build, all_steps, isolation)
    known = {s.number: found for s in order if verdicts is not None and s.number not in quick
             for found in [verdicts.load(s)] if found is not None}
    results: dict[str, StepResult] = {}
    kit: bundle.Bundle | Exception | None = None
    if len(quick) + len(known) < len(order):
        # The kit's side: built once per machine (bundle.py); the first check, or the warm-up, builds it.
        # Only the steps this check builds, where that is not every step (bundle.ensure's parts).
        parts = [s.number for s in order if s.number not in quick and s.number not in known]
        try:
            kit = bundle.ensure(detect_undefined(),
                                lambda: progress.phase("building the kit's side, once for this machine"),
                                parts=None if len(parts) == len(all_steps) else parts)
        except Exception as e:      # noqa: BLE001 -- the kit's or the machine's: every step not graded
            kit = e

    def judge(step: Step, built: Built | Exception | None) -> None:
        if step.number in known:
            results[step.number] = known[step.number]
        elif built is None:
            results[step.number] = untouched_result(step, quick[step.number])
        elif isinstance(built, Exception):
            results[step.number] = not_graded(step, f"the kit failed building it: {faults.describe(built)}")
        else:
            try:
                results[step.number] = judge_step(build, step, built, results, isolation)
            except Exception as e:      # noqa: BLE001 -- the kit's fault (a full disk): the step has no verdict
                results[step.number] = not_graded(step, f"the kit failed running it: {faults.describe(e)}")
            if verdicts is not None:
                verdicts.store(results[step.number])
        if step.number in wanted:
            progress.result(results[step.number])

    judges = InOrder()      # steps are judged in course order, each while the next one builds
    try:
        for s in order:
            built: Built | Exception | None = None
            if s.number not in quick and s.number not in known:
                try:
                    if isinstance(kit, Exception):
                        raise kit
                    built = build_step(build, s, kit, isolation,
                                       lambda done, total, s=s: progress.building(s, done, total))
                except Exception as e:      # noqa: BLE001 -- the kit's or the machine's: not graded
                    built = e
            judges.submit(judge, s, built)
    except BaseException:
        judges.finish(raising=False)    # the build's error, not a judge's, once the judges have ended
        raise
    judges.finish()
    return [results[s.number] for s in steps]
