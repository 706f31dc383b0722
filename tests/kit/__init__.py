"""The kit's self-test, a pytest suite (conftest.py): one module per command or concern (check.py for
./kit check, render.py for ./kit render, ...)."""
