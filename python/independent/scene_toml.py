"""The TOML tables a body scene ends with (issue 19), shared by the independent scripts:
`clamped` (if any), [obstacle], [mass], [scheme], [time]."""


def body_tail(c, scheme):
    """Lines from solid.clamped to the end, for a case dict with normal, point, contact,
    clamped, mass, dt, end."""
    fmt = lambda v: ", ".join(repr(float(x)) for x in v)
    lines = [f'clamped = "{c["clamped"]}"'] if c["clamped"] else []
    lines += ["[obstacle]", f"normal = [{fmt(c['normal'])}]", f"point = [{fmt(c['point'])}]", f'contact = "{c["contact"]}"',
              "[mass]", f'kind = "{c["mass"]}"'] + ([f"weights = [{fmt(c['weights'])}]"] if c.get("weights") is not None else []) + [
              "[scheme]", f'kind = "{scheme}"'] + [f"{k} = {c[k]!r}" for k in ("beta", "gamma") if c.get(k) is not None] + [
              "[time]", f"dt = {c['dt']!r}",
              f"end = {c['end']!r}"]
    return lines
