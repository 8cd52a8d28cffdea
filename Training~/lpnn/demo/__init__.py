"""The headless demo of the README's main job (`lpnn demo`)."""
