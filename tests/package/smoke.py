"""A first use of an installed crawlopt package, run from outside the source tree: the bundled
three-block example's optimal gait (J* = 2.6, theory §10's reference value, certified globally among
gaits of at most K slip phases) and the periodic regime of the three-block sine actuation
(1/2 + sqrt(2) per period, as in tests/cli_messages.rs). Prints one line
`test result: LABEL. N passed; M failed` for the test suite's count; exits 1 on a failure.

    python tests/package/smoke.py EXAMPLES_DIR LABEL
"""

import math
import os
import sys


def main() -> int:
    examples, label = sys.argv[1], sys.argv[2]
    import crawlopt as co

    checks = []
    # The installed package, not the source tree's python/crawlopt.
    checks.append(("installed", "site-packages" in os.path.dirname(co.__file__)))
    m = co.load(os.path.join(examples, "three_blocks_gait.toml"))
    r = co.optimize(m.crawler, m.gait_problem, certify=True)
    checks.append(("optimum 2.6", abs(r.objective - 2.6) < 1e-9))
    checks.append(("certificate", r.certificate["kind"] == "global_k_phases"))
    m2 = co.load(os.path.join(examples, "three_blocks_sine.toml"))
    s = co.simulate(m2.crawler, m2.actuation)
    checks.append(("sine orbit", abs(s.displacement_per_period - (0.5 + math.sqrt(2))) < 1e-9))
    failed = [name for name, ok in checks if not ok]
    for name in failed:
        print(f"{label}: FAILED {name}", file=sys.stderr)
    print(f"test result: {label}. {len(checks) - len(failed)} passed; {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
