"""Tosses that land on a table and bounce: a MuJoCo rigid-body engine between exact flights."""
