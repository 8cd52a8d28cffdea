"""The headless demo of the README's main job (`lpnn demo`)."""

# Here rather than in run.py so that `lpnn --help` can show it without importing the placement code.
DEMO_LEVEL = "oa_dm1"
