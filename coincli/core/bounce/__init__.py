"""Tosses that land on a table and bounce: a MuJoCo rigid-body engine between exact flights
(:mod:`.engine`), many seeded tosses across worker processes (:mod:`.runs`), and the aspect ratio
for a chance of landing on a side (:mod:`.design`)."""
