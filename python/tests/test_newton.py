"""The orbit search's ``newton`` keyword: Newton-Krylov steps (default) against Anderson alone
(``crawlopt simulate --no-newton``) on the bench gait of 30 blocks."""

import crawlopt as co
import pytest


def test_newton_false_searches_with_anderson_alone_and_finds_the_same_displacement():
    n = 29
    c = co.Crawler(blocks=n + 1, stiffness=1.0, mu_forward=1.0, mu_backward=3.3)
    act = co.Actuation.sine(period=1.0, amplitude=[2.0] * n, phase_deg=[90.0 * j for j in range(n)])
    newton = co.simulate(c, act, method="catching_up", periods=0)
    anderson = co.simulate(c, act, method="catching_up", periods=0, newton=False)
    assert newton.search == "newton"
    assert newton.newton_steps >= 1 and newton.tangent_products >= 1
    assert anderson.search == "anderson"
    assert anderson.newton_steps == 0 and anderson.tangent_products == 0
    assert newton.displacement_per_period == pytest.approx(
        anderson.displacement_per_period, abs=1e-10
    )
