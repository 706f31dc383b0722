"""One module per ./kit command, each with HELP, register(parser) and run(args) -> exit status.
The table of commands (their order, who they are for) is kitlib/cli.py's COMMANDS."""
