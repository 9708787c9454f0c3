"""Every gallery example's own end-to-end check (``nonideal examples run NAME``) passes: its
derivation, simulation and comparison with the source's closed form or numbers.  (One of them
had an absolute tolerance on multipliers of size ~100 and failed without any test noticing.)"""

import pytest

from nonideal import gallery


@pytest.mark.slow
@pytest.mark.parametrize("name", gallery.names())
def test_example_run_is_ok(name):
    result = gallery.run(name, verbose=False)
    assert result["ok"], {k: v for k, v in result.items() if k != "ok"}
