"""The error-driven reference placements (quality.md §3): decimation by removal cost, faithful and fast, and the
blockwise reference of whole levels. Imports lpnn.quality.metric, no other placement module."""
