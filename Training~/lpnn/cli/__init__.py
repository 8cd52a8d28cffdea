"""The `lpnn` command line. Each `*_cmd.py` module here adds one subcommand via `register`."""
