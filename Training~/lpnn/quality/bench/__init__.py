"""The speed/accuracy benchmark (quality.md §6, benchmarks.md): its rows and CSV, the methods and yardstick it
measures, the run per capture and the figures."""
