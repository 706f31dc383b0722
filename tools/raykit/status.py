"""The kit's answers in words and numbers: exit statuses, a step's states, a case's statuses.

Every module uses these names; the strings are what the JSON reports, CSV files and Gradescope
carry, so they never change meaning.
"""

# --- exit statuses of ./kit ------------------------------------------------------------
OK = 0              # everything asked for worked (every checked step is done)
FAILED = 1          # it ran, and something is not right yet: a case fails, a build fails
USAGE = 2           # the command line or what it names is wrong; the message says how
SETUP = 3           # the machine lacks a tool the kit cannot install by itself
INTERRUPTED = 130   # Ctrl-C, as a shell reports it

# --- a step's state after ./kit check ----------------------------------------------------
DONE = "done"                   # every basic and hidden case passes
PARTIAL = "partial"             # started, some case fails
NOT_STARTED = "not_started"     # every case reaches the stub's not_implemented_yet
MISSING = "missing"             # a file the step needs is not there
NO_COMPILE = "no_compile"       # the student's files do not compile or link
WAITING = "waiting"             # an earlier step it builds on is not done (a handout only)
NOT_GRADED = "not_graded"       # a fault of the kit, the machine or the accounting: no verdict (notgraded.py)
OLD_BROKEN = "broken"           # its name in records written before "not graded" (read as not graded)

STATE_WORDS = {
    DONE: "done", PARTIAL: "some cases fail", NOT_STARTED: "not started", MISSING: "a file is missing",
    NO_COMPILE: "does not compile", WAITING: "waits for an earlier step", NOT_GRADED: "not graded",
    OLD_BROKEN: "not graded",
}

# --- a submission's state in ./kit grade's CSV, when it has no results record -----------------------
# An upload with no step file, or none that could be read (empty, an unreadable archive, too many
# files): the student's, not the grader's (issue 55: it was listed as "not graded"). It scores 0 of
# the maximum and leaves ./kit grade's exit status as it is (docs/instructors.md, "Not graded").
NOTHING_SUBMITTED = "nothing submitted"
NOTHING_SUBMITTED_STATES = (NOTHING_SUBMITTED, "no steps")     # "no steps": its name in older CSVs

# --- a case's status -----------------------------------------------------------------------
PASS, FAIL, THREW, CRASHED, TIMED_OUT, NOT_RUN = "pass", "fail", "threw", "crashed", "timed_out", "not_run"
GRADER_ERROR = "grader_error"   # no verdict, the grader's fault (a sandbox that could not start, the judge
                                # stopped, a full disk): the step is not graded, no points lost

# A case that ran out of time, or never ran because the step's budget was spent, gave no answer: what a
# loop or a slow step fails says nothing of which slip it is (issue 46: a looping submission was matched
# exactly to a slip), so a step with such a case is matched to no slip, by ./kit check (slips.match) and
# by the class report (report/pages.analyse) alike.
NO_ANSWER = (TIMED_OUT, NOT_RUN)

STATUS_WORDS = {
    PASS: "passed", FAIL: "wrong answer", NOT_STARTED: "not started", THREW: "threw an exception",
    CRASHED: "crashed", TIMED_OUT: "timed out", NOT_RUN: "not run", NO_COMPILE: "does not compile",
    MISSING: "file missing", WAITING: "waits for an earlier step", GRADER_ERROR: "not graded (the grader's fault)",
}
