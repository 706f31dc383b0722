"""./kit test, the kit's self-test: one module per command or concern (check.py for ./kit check,
render.py for ./kit render, ...), run in the order of harness.MODULES."""
