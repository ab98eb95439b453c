#!/usr/bin/env python3
"""Writes the photometric test files of tests/data/photometry/ (run from the
repository root; the output is deterministic and committed).

Both hold one distribution, asymmetric by construction so that a reader
that swaps or mirrors C-planes is caught:

    I(C, gamma) = I0 cos(gamma) (1 + 0.5 cos C + 0.3 sin C),  gamma <= 90
                = 0                                          gamma >  90

in candela, C and gamma in degrees (C0: 1.5 I0, C90: 1.3 I0, C180: 0.5 I0,
C270: 0.7 I0 straight down). Its integral over the sphere is pi I0 (the
sine and cosine of C integrate to 0), so with I0 = 1000 / pi cd the
luminaire sends 1000 lm:

  asymmetric.ldt  EULUMDAT, Isym 0, 24 C-planes (15 degrees), 37 gammas
                  (5 degrees, 0-180); one lamp set of 2000 lm, LORL 50%,
                  so the luminaire's flux is 1000 lm and the values are
                  cd/klm of 2000 lm: I / 2.
  asymmetric.ies  IES LM-63-2002, 25 horizontal angles 0-360 (the 360
                  plane repeats 0), 19 vertical angles 0-90; one lamp of
                  1000 lm, candela multiplier 2, so the values are I / 2.
"""
import math

I0 = 1000 / math.pi


def intensity(c, g):
    if g > 90:
        return 0.0
    c, g = math.radians(c), math.radians(g)
    return I0 * math.cos(g) * (1 + 0.5 * math.cos(c) + 0.3 * math.sin(c))


def ldt():
    cs = [15 * k for k in range(24)]
    gs = [5 * k for k in range(37)]
    lines = ["xrad test luminaire (tools/gen_photometry.py)", "1", "0", "24", "15", "37", "5",
             "report 1", "asymmetric downlight", "XR-1", "asymmetric.ldt", "2026-12-06 xrad",
             "600", "600", "80", "580", "580", "0", "0", "0", "0",
             "100", "50", "1", "0", "1",
             "1", "LED", "2000", "3000", "1A", "20"]
    lines += ["0.5"] * 10
    lines += ["%g" % c for c in cs] + ["%g" % g for g in gs]
    lines += ["%.6f" % (intensity(c, g) / 2) for c in cs for g in gs]
    return "\r\n".join(lines) + "\r\n"


def ies():
    hs = [15 * k for k in range(25)]
    vs = [5 * k for k in range(19)]
    out = ["IESNA:LM-63-2002", "[TEST] xrad test luminaire (tools/gen_photometry.py)",
           "[MANUFAC] xrad", "[LUMINAIRE] asymmetric downlight", "TILT=NONE",
           "1 1000 2 %d %d 1 2 0.6 0.6 0.08" % (len(vs), len(hs)), "1 1 20"]
    out.append(" ".join("%g" % v for v in vs))
    out.append(" ".join("%g" % h for h in hs))
    for h in hs:
        vals = ["%.6f" % (intensity(h, v) / 2) for v in vs]
        for i in range(0, len(vals), 10):  # lines of ten, as tools write them
            out.append(" ".join(vals[i:i + 10]))
    return "\n".join(out) + "\n"


with open("tests/data/photometry/asymmetric.ldt", "w", newline="") as f:
    f.write(ldt())
with open("tests/data/photometry/asymmetric.ies", "w", newline="") as f:
    f.write(ies())
