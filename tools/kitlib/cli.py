"""The instructor's commands, after the students' (raykit/cli.py, which parses and dispatches both).

The kit's driver is two packages, along its two audiences:
  - tools/raykit, the student's runtime (./kit check, watch, hint, debug, render, reset and what they
    import): the standard library only; all a handout ships of the driver;
  - tools/kitlib, the instructor's toolchain (grading, the platforms, the report, the docs and
    slides, the bench's reading, the self-test): it imports raykit, never the reverse, and may use
    Debian 12's packages.
The layers self-test holds both rules (tests/kit/layers.py).
"""

from __future__ import annotations

from raykit import cli as students
from raykit.cli import INSTRUCTOR, STUDENT, Command, Parser, handout

# The table's words, re-exported: the instructor's side reads every command from here.
__all__ = ["COMMANDS", "INSTRUCTOR", "STUDENT", "Command", "Parser", "handout", "build_parser", "main"]
STUDENTS = students.COMMANDS


def _i(name: str, module: str, help: str) -> Command:
    return Command(name, module, INSTRUCTOR, help, package="kitlib")


COMMANDS = STUDENTS + [
    _i("docs", "docs", "write the course's documentation (lectures, API, images) as HTML that reads offline"),
    _i("bench", "bench", "measure speed against error of the ray-sphere formulas, the kit's code and Embree"),
    _i("test", "selftest", "the kit's self-test: solutions pass, stubs are not started, tools work (CI)"),
    _i("course", "course", "print the course's scale (course.json): steps, case groups, points, the Gradescope total"),
    _i("grade", "grade", "grade a class (one folder or .zip per student, steps at any depth) into a CSV"),
    _i("report", "report", "the class report of a grading (offline HTML): scores, failed cases, slips, incidents, "
                           "similar work"),
    _i("handout", "handout", "write the students' copy of the kit: the committed stubs, no code that computes an "
                             "answer"),
    _i("exact", "exact", "check (--refresh: rewrite) the precomputed exact answers of the ★ tier"),
    _i("refresh", "refresh", "after a change to the course: rewrite what is stale (tables, pictures, "
                             "case lists, exact answers, signatures), run the touched self-tests"),
    _i("mutant", "mutant", "write a mutant (a slip in the reference answer) as a patch: new, edit, save"),
    _i("slides", "slides", "write a slide deck per lecture (lectures/slides/) as offline HTML, --pdf also PDF"),
    _i("autograder", "autograder", "write the Gradescope autograder zip: the kit, with setup.sh and run_autograder"),
    _i("classroom", "classroom", "write GitHub Classroom's autograding workflow into a handout (partial credit per "
                                 "case)"),
    _i("prairielearn", "prairielearn", "write PrairieLearn questions, the grader's entry point and its Docker image"),
]


def main(argv: list[str]) -> int:
    return students.main(argv, COMMANDS)


def build_parser(chosen: str | None) -> Parser:
    """./kit's parser with every command (raykit/cli.py's build_parser)."""
    return students.build_parser(chosen, COMMANDS)
