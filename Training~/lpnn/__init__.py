"""LPNN Probes trainer: the Python side of the com.lpnn.probes Unity package."""

__version__ = "0.1.0"
