# The two commands of the README. Both set up what they need on a fresh Debian machine.
.PHONY: test demo

# Every test: C# core (Mono + NUnit), Unity-layer compile check, Python trainer (pytest).
test:
	@bash "Tools~/test.sh"

# The main job: a held-out OpenArena level scored by the shipped model, placed, measured.
demo:
	@bash "Tools~/demo.sh"
