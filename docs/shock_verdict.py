"""The worked example of docs/shock-verdict.md: a pump skid on four shock
mounts (pipeline/scenes/skid.toml, installed as flexbed/scenes/skid.toml)
under a 30 g / 11 ms half-sine in z and 20 g in y,
qualified against its limits with the bed rigid, then the same verdict's
figures with the bed flexible. Run: ``python docs/shock_verdict.py``
(about 10 s once compiled; the tests run it too)."""

from importlib import resources

import flexbed

scene = flexbed.load_scene(resources.files("flexbed") / "scenes" / "skid.toml")

# 1. The verdict with the rigid bed (as `flexbed qualify pipeline/scenes/skid.toml`).
q = flexbed.qualify(scene)
print(f"rigid bed: {'PASS' if q.passed else 'FAIL'}")

# 2. Which limit comes closest, and when.
used = [(ratio, when, m.name, kind) for m in q.verdict.mounts
        for kind, (ratio, when) in m.usage().items()]
for ratio, when, name, kind in sorted(used, reverse=True)[:3]:
    at = "at rest" if when != when else f"at t = {1e3 * when:.1f} ms"
    print(f"  mount {name}: {100 * ratio:.1f} % of its {kind} limit {at}")
for m in q.verdict.mounts:
    if m.contacts:
        print(f"  mount {m.name} bottoms {m.contacts}x from t = {1e3 * m.first_contact:.1f} ms, "
              f"peak contact force {m.peak_contact_force:.0f} N at "
              f"t = {1e3 * m.peak_contact_time:.1f} ms")
for b in q.verdict.bodies:
    if b.fragility is not None:
        print(f"  {b.name}: {b.peak_acceleration / 9.80665:.2f} g of its "
              f"{b.fragility.given:g} g at t = {1e3 * b.time:.1f} ms")
for c in q.verdict.clearances:
    print(f"  {c.clearance.name}: {1e3 * c.minimum:.2f} mm at t = {1e3 * c.time:.1f} ms, "
          f"margin {1e3 * c.margin:.2f} mm")

# 3. Rigid, flexible and damped flexible bed side by side.
c = flexbed.compare(scene)
print()
print(c.verdict_table())
for case, v in c.verdicts.items():
    for reason in v.reasons:
        print(f"{case}: {reason}")
