"""scripts/size_trend.py's computation on made-up campaigns whose size effect is planted: three
sizes, 12 samples, three rates, with p_n(phi) = p0(phi) (1 + a g(n)) times independent
per-sample noise of 3%. With g(n) = ln(n / 32768) the ratio R of the 8192 and 16384 effects is
ln 4 / ln 2 = 2; with g(n) = 32768 / n - 1 it is 3. trend() must find each within three of its
jackknife errors and closer to the planted law than to the other, and refuse an ensemble with
fewer than two samples. (Reading the runs is jamio.load_runs', tested in test_jamio.)

Usage (ctest runs it): python3 -m pytest tests/test_size_trend.py --source .
"""

import math
import sys

import numpy as np
import pytest

SIZES = (8192, 16384, 32768)
RATES = (-7.5, -8.0, -8.5)


@pytest.fixture
def size_trend(source):
    sys.path.insert(0, str(source / "scripts"))
    import size_trend
    return size_trend


def planted(law, samples=12, short=None):
    """jamio.load_runs' columns (as_frame=False) of a campaign with the effect `law` planted."""
    rng = np.random.default_rng(7)
    phi = np.round(np.arange(0.8200, 0.8400001, 0.0005), 6)
    cols = {k: [] for k in ("n", "compression_rate", "sample", "packing_fraction", "pressure")}
    for n in SIZES:
        for r in RATES:
            for s in range(1 if short == (n, r) else samples):
                p = 1e-3 * (phi / 0.82) ** 8 * (1 + 0.12 * law(n)) * (1 + 0.03 * rng.normal())
                cols["n"] += [n] * len(phi)
                cols["compression_rate"] += [10.0 ** r] * len(phi)
                cols["sample"] += [float(s)] * len(phi)
                cols["packing_fraction"] += list(phi)
                cols["pressure"] += list(p)
    return {k: np.array(v) for k, v in cols.items()}


@pytest.mark.parametrize("law,expected,other", [
    (lambda n: math.log(n / 32768), 2.0, 3.0),
    (lambda n: 32768 / n - 1, 3.0, 2.0)], ids=["ln_n", "one_over_n"])
def test_planted_law_is_found(size_trend, law, expected, other):
    t = size_trend.trend(planted(law), [8192, 16384], 32768, RATES, 0.8289, 0.8369)
    ratio, err = t["ratio"]
    assert 0 < err < 0.5
    assert abs(ratio - expected) < 3 * err, t
    assert abs(ratio - other) > abs(ratio - expected), t
    # The Delta itself: the planted 0.12 g(16384), within three errors.
    d, e = t["delta"][16384]
    assert abs(d - 0.12 * law(16384)) < 3 * e, t


def test_too_few_samples_refused(size_trend):
    with pytest.raises(ValueError, match="n 16384 log10 rate -8.0: 1 finished samples"):
        size_trend.trend(planted(lambda n: 0.0, short=(16384, -8.0)), [8192, 16384], 32768,
                         RATES, 0.8289, 0.8369)
