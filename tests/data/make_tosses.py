"""Write tests/data/tosses.csv: synthetic tosses in the paper's design (Sec. IV).

Stacks of 1 to 8 paper quarters (24 mm x 1.75 mm) and two aluminium discs (25 mm rod), 100
tosses each, drawn (numpy seed 2024) from psi ~ normal(90 deg, 18 deg) truncated to [0, 180],
i.e. a hand toss that is not quite a Keller flip.  Two rows give only sides and n, as when the
faces were not told apart.  These are NOT the paper's measurements (it prints none).

    python tests/data/make_tosses.py > tests/data/tosses.csv
"""

import math

import numpy as np

from coincli.core.averages import marginal
from coincli.core.coins import get_coin, stack_xi
from coincli.core.densities import Normal

rng = np.random.default_rng(2024)
dens = Normal(math.pi / 2, math.radians(18))
print("# synthetic: psi ~ normal(90, 18) deg; see make_tosses.py")
print("label,coin,count,diameter,thickness,heads,sides,tails,n")
q = get_coin("paper-quarter")
for k in range(1, 9):
    p = np.array(marginal(stack_xi(q, k), dens))
    h, s, t = rng.multinomial(100, p / p.sum())
    if k in (2, 5):
        print(f"{k}-coin,paper-quarter,{k},,,,{s},,100")
    else:
        print(f"{k}-coin,paper-quarter,{k},,,{h},{s},{t},")
for thick in (20, 30):
    p = np.array(marginal(thick / 25, dens))
    h, s, t = rng.multinomial(100, p / p.sum())
    print(f"rod {thick} mm,,,25mm,{thick}mm,{h},{s},{t},")
