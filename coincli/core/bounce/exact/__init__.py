"""An exact contact for a rigid cylinder on a rigid plane (issue 39, stage 1): plain functions,
numbers in and records out; nothing in the product uses them yet.

- :mod:`.body`: the cylinder (mass, moments of inertia, the lowest point of its rim).
- :mod:`.impact`: the impact law.  Darboux-Keller integration in the normal impulse with
  Coulomb friction (slip, stick, reversal) and Stronge's energetic coefficient of restitution,
  at one rim point; and the square impact of a whole face.
- :mod:`.flat`: lying flat on a face, sliding and spinning, with the friction integrated over
  the face at uniform pressure (Farkas et al., PRL 90, 248302, 2003) and torsional resistance.
- :mod:`.rim`: on one rim point, rolling or slipping, with rolling and spinning resistance; the
  normal force from the unilateral constraint.
- :mod:`.side`: lying on the curved side (a line contact), rolling or sliding.

The laws, their sources and the known answers with their measured errors are in
docs/contact-models.md, "An exact contact (stage 1)".  World frame: z up, the plane z = 0;
SI units throughout.
"""
