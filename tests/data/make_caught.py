"""Write tests/data/caught.csv: synthetic caught flips of 48 people, built like Bartos et al.
(2023, arXiv:2310.04153; 350,757 flips of 48 people), NOT their data.

Each person flips a catalog coin (a mix of euro coins and a quarter) and catches it; their
tossing style is a spread of psi: log sigma_i ~ normal(log 7.5 deg, 0.35), i.e. a median tosser
at 7.5 deg and tossers differing by a factor of about 1.4.  Flip counts per person are drawn
around the published mean (about 7,300 a person); each flip starts on heads or tails at random,
and lands on the same side with P(H) / (P(H) + P(T)) under psi ~ normal(90 deg, sigma_i)
truncated to [0, 180] (coincli.core.stats.caught.same_chance).  The rows give the four cells
hsame, hdiff, tsame, tdiff as such data sets publish them.  numpy seed 2023.

    python tests/data/make_caught.py > tests/data/caught.csv
"""

import math

import numpy as np

from coincli.core.coins import get_coin
from coincli.core.stats.caught import same_chance

rng = np.random.default_rng(2023)
coins = ["euro-1", "euro-2", "euro-50c", "euro-20c", "quarter"]
print("# synthetic: 48 tossers, log sd of psi ~ normal(log 7.5 deg, 0.35); see make_caught.py")
print("label,coin,hsame,hdiff,tsame,tdiff")
for i in range(48):
    coin = get_coin(coins[i % len(coins)])
    sigma = math.radians(7.5) * math.exp(0.35 * rng.standard_normal())
    q = float(same_chance(coin.thickness_mm / coin.diameter_mm, sigma))
    n = int(rng.integers(2000, 12600))
    n_heads = int(rng.binomial(n, 0.5))
    hs = int(rng.binomial(n_heads, q))
    ts = int(rng.binomial(n - n_heads, q))
    print(f"tosser-{i + 1:02d},{coin.name},{hs},{n_heads - hs},{ts},{n - n_heads - ts}")
