"""tools/ as a package, so that `python3 -m unittest` run from the repository root finds
test_selftests.py (the self-tests of ./kit test, collected for unittest)."""
