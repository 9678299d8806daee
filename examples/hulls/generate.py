"""Generates examples/hulls/*.xml (run: python3 examples/hulls/generate.py from the repository root)."""
import math, os

OUT = os.path.dirname(os.path.abspath(__file__))

def fmt(v, digits):
    t = ("%.*f" % (digits, v)).rstrip("0").rstrip(".")
    return "0" if t in ("-0", "") else t

def arc(c, r, a0, a1, n):
    """n+1 points on an arc from angle a0 to a1 (degrees), both ends included."""
    return [(c[0] + r * math.cos(math.radians(a0 + (a1 - a0) * k / n)),
             c[1] + r * math.sin(math.radians(a0 + (a1 - a0) * k / n))) for k in range(n + 1)]

def line(p, q, n):
    return [(p[0] + (q[0] - p[0]) * k / n, p[1] + (q[1] - p[1]) * k / n) for k in range(n + 1)]

def join(*parts):
    pts = []
    for part in parts:
        for p in part:
            if pts and math.dist(pts[-1], p) < 1e-9:
                continue
            pts.append(p)
    return pts

def normalize(vectors):
    m = max(math.hypot(*v) for v in vectors)
    return [(v[0] / m, v[1] / m) for v in vectors]

def write(name, header, half_beam, points, closed, rigid, modes, digits=4):
    lines = ['<?xml version="1.0" encoding="UTF-8"?>', "<!--"]
    lines += ["  " + h for h in header]
    lines += ["-->",
              '<hull name="%s" half_beam="%s" units="m" version="1">' % (name, fmt(half_beam, 4)),
              '  <contour closed="%s">' % ("true" if closed else "false")]
    lines += ['    <point x="%s" y="%s"/>' % (fmt(x, digits), fmt(y, digits)) for x, y in points]
    lines += ["  </contour>"]
    for dof, kind, ref in rigid:
        if ref is None:
            lines.append('  <rigid name="%s" kind="%s"/>' % (dof, kind))
        else:
            lines.append('  <rigid name="%s" kind="%s" x="%s" y="%s"/>'
                         % (dof, kind, fmt(ref[0], digits), fmt(ref[1], digits)))
    for mname, comment, vecs in modes:
        assert len(vecs) == len(points)
        lines.append("  <!-- %s -->" % comment)
        lines.append('  <mode name="%s">' % mname)
        lines += ['    <u x="%s" y="%s"/>' % (fmt(u, 6), fmt(v, 6)) for u, v in vecs]
        lines.append("  </mode>")
    lines.append("</hull>")
    with open(os.path.join(OUT, name + ".xml"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(name, len(points), "points")

# ---------------------------------------------------------------- barge
B, T, RB = 10.0, 5.0, 2.0      # half-beam, draft, bilge radius
left_side = line((-B, 0), (-B, -(T - RB)), 3)
left_bilge = arc((-B + RB, -(T - RB)), RB, 180, 270, 8)
bottom = line((-B + RB, -T), (B - RB, -T), 16)
right_bilge = arc((B - RB, -(T - RB)), RB, 270, 360, 8)
right_side = line((B, -(T - RB)), (B, 0), 3)
barge = join(left_side, left_bilge, bottom, right_bilge, right_side)

def on_bottom(p):
    return abs(p[1] + T) < 1e-9 and abs(p[0]) <= B - RB + 1e-9

def xi(p):  # 0..1 across the flat bottom
    return (p[0] + B - RB) / (2 * (B - RB))

sym = [(0.0, (1 - math.cos(2 * math.pi * xi(p))) / 2) if on_bottom(p) else (0.0, 0.0) for p in barge]
anti = [(0.0, math.sin(math.pi * xi(p)) * math.sin(2 * math.pi * xi(p))) if on_bottom(p) else (0.0, 0.0)
        for p in barge]
def side_shape(p):
    if abs(abs(p[0]) - B) < 1e-9 and p[1] >= -(T - RB) - 1e-9:
        eta = (p[1] + T - RB) / (T - RB)             # 0 at the bilge, 1 at the waterline
        v = (1 - math.cos(math.pi * eta / 2))         # clamped at the bilge
        return (-v if p[0] < 0 else v, 0.0)
    return (0.0, 0.0)
breathing = [side_shape(p) for p in barge]
write("barge",
      ["Rectangular barge section with rounded bilges: beam 20 m, draft 5 m, bilge radius 2 m.",
       "Elastic modes (displacement per unit generalized coordinate, metres, max 1):",
       "bottom plate bending between the bilges (symmetric, antisymmetric), and side",
       "breathing (both sides outward, clamped at the bilges). Roll is about the origin",
       "on the free surface, at the centre plane."],
      B, barge, False,
      [("sway", "sway", None), ("heave", "heave", None), ("roll", "roll", (0, 0))],
      [("bottom_symmetric", "bottom plating, one half-wave up between the bilges", normalize(sym)),
       ("bottom_antisymmetric", "bottom plating, up on the right, down on the left", normalize(anti)),
       ("side_breathing", "sides outward, clamped at the bilges", normalize(breathing))])

# ---------------------------------------------------------------- midship section
HB, D = 12.0, 8.0                       # half-beam at the waterline, draft at the keel
dead, flare, rb = math.radians(12), math.radians(10), 3.0
keel = (0.0, -D)
d1 = (math.cos(dead), math.sin(dead))                # bottom, outward and up
d2 = (math.sin(flare), math.cos(flare))              # side, upward and outward
# corner: keel + a d1 = W - b d2, W = (HB, 0)
det = d1[0] * (-d2[1]) - (-d2[0]) * d1[1]
rx, ry = HB - keel[0], 0 - keel[1]
a = (rx * (-d2[1]) - (-d2[0]) * ry) / det
corner = (keel[0] + a * d1[0], keel[1] + a * d1[1])
turn = math.pi - (dead + flare) - math.pi / 2        # interior angle / 2 ... computed below
phi = math.acos(-(d1[0] * d2[0] + d1[1] * d2[1]))    # angle between -d1 and d2 (interior)
tlen = rb / math.tan(phi / 2)
t1 = (corner[0] - tlen * d1[0], corner[1] - tlen * d1[1])
t2 = (corner[0] + tlen * d2[0], corner[1] + tlen * d2[1])
# bilge centre: from t1 along the inward normal of the bottom (-sin, cos)
cen = (t1[0] - rb * math.sin(dead), t1[1] + rb * math.cos(dead))
a0 = math.degrees(math.atan2(t1[1] - cen[1], t1[0] - cen[0]))
a1 = math.degrees(math.atan2(t2[1] - cen[1], t2[0] - cen[0]))
nb = max(1, round(math.dist(keel, t1) / 1.0))
ns = max(1, round(math.dist(t2, (HB, 0)) / 1.0))
right = join(line(keel, t1, nb), arc(cen, rb, a0, a1, 8), line(t2, (HB, 0.0), ns))
left = [(-x, y) for x, y in reversed(right)]
mid = join(left, right)

inward_bottom_r = (-math.sin(dead), math.cos(dead))   # normal into the body, right bottom
def bottom_xi(p):  # 0 at the keel, 1 at the bilge tangent, None off the bottom
    if abs(p[0]) <= t1[0] + 1e-9 and p[1] <= t1[1] + 1e-9:
        return abs(p[0]) / t1[0]
    return None
def bottom_mode(p, antisym):
    s = bottom_xi(p)
    if s is None:
        return (0.0, 0.0)
    w = math.sin(math.pi * s) ** 2                    # clamped at keel girder and bilge
    n = inward_bottom_r if p[0] >= 0 else (-inward_bottom_r[0], inward_bottom_r[1])
    sign = -1.0 if (antisym and p[0] < 0) else 1.0
    return (sign * w * n[0], sign * w * n[1])
outward_side_r = (math.cos(flare), -math.sin(flare))  # out of the body, right side
def side_mode(p):
    if abs(p[0]) >= t2[0] - 1e-9 and p[1] >= t2[1] - 1e-9:
        eta = (p[1] - t2[1]) / (0 - t2[1])
        v = 1 - math.cos(math.pi * eta / 2)
        n = outward_side_r if p[0] > 0 else (-outward_side_r[0], outward_side_r[1])
        return (v * n[0], v * n[1])
    return (0.0, 0.0)
write("midship",
      ["Ship midship section: beam 24 m at the waterline, draft 8 m at the keel, 12 degree",
       "deadrise (V-ish bottom), 3 m bilge radius, 10 degree flare of the sides.",
       "Elastic modes (per unit generalized coordinate, metres, max 1): bottom plating",
       "bending between keel girder and bilge normal to the plating, both halves inward",
       "(symmetric) or left outward / right inward (antisymmetric); side shell flexing",
       "outward, clamped at the bilge. Roll is about (0, -3), near the centre of gravity."],
      HB, mid, False,
      [("sway", "sway", None), ("heave", "heave", None), ("roll", "roll", (0, -3))],
      [("bottom_symmetric", "bottom plating, both halves inward", normalize([bottom_mode(p, False) for p in mid])),
       ("bottom_antisymmetric", "bottom plating, right half inward, left half outward",
        normalize([bottom_mode(p, True) for p in mid])),
       ("side_flexing", "side shell outward on both sides", normalize([side_mode(p) for p in mid]))])

# ---------------------------------------------------------------- submerged pontoon
W, H, RC, YC = 6.0, 3.0, 1.5, -12.0      # half-width, half-height, corner radius, centre depth
pont = join(
    line((-W, YC), (-W, YC - H + RC), 2),                                # left side, down
    arc((-W + RC, YC - H + RC), RC, 180, 270, 4),
    line((-W + RC, YC - H), (W - RC, YC - H), 9),                        # bottom
    arc((W - RC, YC - H + RC), RC, 270, 360, 4),
    line((W, YC - H + RC), (W, YC + H - RC), 3),                         # right side, up
    arc((W - RC, YC + H - RC), RC, 0, 90, 4),
    line((W - RC, YC + H), (-W + RC, YC + H), 9),                        # top
    arc((-W + RC, YC + H - RC), RC, 90, 180, 4),
    line((-W, YC + H - RC), (-W, YC), 2)[:-1],                           # back to the start
)
def plate(p, y0, sign):
    if abs(p[1] - y0) < 1e-9 and abs(p[0]) <= W - RC + 1e-9:
        s = (p[0] + W - RC) / (2 * (W - RC))
        return (0.0, sign * (1 - math.cos(2 * math.pi * s)) / 2)
    return (0.0, 0.0)
write("pontoon",
      ["Fully submerged pontoon (closed contour): 12 m wide, 6 m high, 1.5 m corner radius,",
       "centre 12 m below the free surface. Roll is about the pontoon's centre (0, -12).",
       "Elastic modes: bottom plate and top plate bending inward (max 1 m per unit coordinate)."],
      W, pont, True,
      [("sway", "sway", None), ("heave", "heave", None), ("roll", "roll", (0, YC))],
      [("bottom_plate", "bottom plate inward (up)", plate_vecs) for plate_vecs in
       [[plate(p, YC - H, 1.0) for p in pont]]] +
      [("top_plate", "top plate inward (down)", [plate(p, YC + H, -1.0) for p in pont])])

# ---------------------------------------------------------------- Sundsdal et al. (2025) model
# The 2D ship section of the flume experiment (docs/DRIFT.md): beam 0.40 m, draft 0.20 m,
# bilge radius 0.0512 m, centre of gravity 0.106 m above the keel.
SB, ST, SR = 0.2, 0.2, 0.0512
KG = 0.106
model = join(
    line((-SB, 0), (-SB, -(ST - SR)), 6),
    arc((-SB + SR, -(ST - SR)), SR, 180, 270, 6),
    line((-SB + SR, -ST), (SB - SR, -ST), 12),
    arc((SB - SR, -(ST - SR)), SR, 270, 360, 6),
    line((SB, -(ST - SR)), (SB, 0), 6),
)
write("sundsdal",
      ["The 2D ship section of Sundsdal, Greco, Hanssen and Lugni (2025, Ocean Engineering):",
       "beam 0.40 m, draft 0.20 m, bilge radius 0.0512 m, wall-sided. Roll is about the",
       "centre of gravity, 0.106 m above the keel."],
      SB, model, False,
      [("sway", "sway", None), ("heave", "heave", None), ("roll", "roll", (0, KG - ST))],
      [], digits=5)
