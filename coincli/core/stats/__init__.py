"""Counts of tosses against the models: intervals, exact tests, fits across experiments."""
