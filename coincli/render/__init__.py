"""Figures (matplotlib) and text plots (a terminal)."""
