"""One module per instructor's ./kit command, each with register(parser) and run(args) -> exit status.
The table of those commands is kitlib/cli.py's COMMANDS; the students' are raykit/commands/."""
