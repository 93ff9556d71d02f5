#!/usr/bin/env python3
"""Why the hybrid method's contacts converge at order about 1.4 in the step, and what
would make them second order (a model study, session 45; docs/accuracy.md).

usage: python3 bench/verlet_onset.py        (pure Python, about 6 seconds)

Tsuji's dimensionless impact (src/contact/hertz.rs): xi'' = -max(0, xi^(3/2) + alpha
xi^(1/4) xi'), xi(0) = 0, xi'(0) = 1, rebound speed e(alpha). The hybrid method steps a
contact with velocity Verlet from the located touch, the force at the step's end taken
at the half-kicked velocity (as LIGGGHTS does). Its rebound error has two parts:
- the dashpot starts as s^(1/4) (s the time since the touch): velocity Verlet's
  trapezoid over it misses -zeta(-1/4) h^(5/4) alpha (zeta(-1/4) = -0.3205, the
  Navot-Euler-Maclaurin term), order 1.25;
- the half-kicked velocity lags the step's end by h a / 2: an O(h) error of the
  dashpot, which partly cancels the first at these steps.
Three schemes, against the order-2 one at 200,000 steps per contact:
  half      the hybrid method's (peenflow's and LIGGGHTS' velocity Verlet);
  euler     the dashpot at the Euler-predicted end velocity v + h a, no onset term;
  corrected euler, plus the missed impulse -zeta(-1/4) alpha h^(5/4) after the first step.
Printed: the rebound speed's error at 25 to 400 steps per contact (peenflow's 20 ns is
about 50 on these shots), and the observed orders.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import options  # noqa: E402

ZETA_M14 = -0.32045126422857734  # zeta(-1/4)
T_CONTACT = 3.2  # about the dimensionless contact time


def rebound(alpha, h, scheme):
    x, v = 0.0, 1.0
    a = 0.0  # no force at the touch
    j = 0
    while True:
        v_half = v + 0.5 * h * a
        x += h * v_half
        vd = v_half if scheme == "half" else v_half + 0.5 * h * a
        a = -max(0.0, x ** 1.5 + alpha * x ** 0.25 * vd) if x > 0.0 else 0.0
        v = v_half + 0.5 * h * a
        j += 1
        if scheme == "corrected" and j == 1:
            v += ZETA_M14 * alpha * h ** 1.25
        if x <= 0.0 and j > 2:
            return -v


def reference(alpha):
    return rebound(alpha, T_CONTACT / 200000, "corrected")


def alpha_for(e):
    lo, hi = 0.0, 2.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if reference(mid) > e:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def main():
    options(__doc__)
    steps = [25, 50, 100, 200, 400]
    print("steps per contact:", " ".join(f"{n:>8}" for n in steps))
    for e in (0.7, 0.9):
        alpha = alpha_for(e)
        ref = reference(alpha)
        print(f"restitution {e} (alpha {alpha:.4f}, rebound {ref:.6f}):")
        for scheme in ("half", "euler", "corrected"):
            errs = [abs(rebound(alpha, T_CONTACT / n, scheme) - ref) for n in steps]
            orders = [math.log2(errs[i] / errs[i + 1]) for i in range(len(errs) - 1)]
            print(f"  {scheme:<10}", " ".join(f"{x:8.2e}" for x in errs),
                  "  orders", " ".join(f"{o:.2f}" for o in orders))


if __name__ == "__main__":
    main()
