"""One module per student's ./kit command, each with HELP, register(parser) and run(args) -> exit status.
The table of commands (their order, who they are for) is raykit/cli.py's COMMANDS;
the instructor's commands are kitlib/commands/."""
