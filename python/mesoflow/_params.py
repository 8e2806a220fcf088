"""Keyword arguments onto the C++ parameter structs (one rule for every scene): an unknown keyword
raises TypeError listing the known ones; values go through pybind11 (a wrong type raises TypeError);
range checks are the C++ validate() of each scene."""


def check_keywords(kind, keys, allowed):
    bad = sorted(set(keys) - set(allowed))
    if bad:
        raise TypeError("%s: unknown parameter%s %s; known: %s" % (kind, "s" if len(bad) > 1 else "", ", ".join(bad),
                                                                    ", ".join(sorted(allowed))))


def fill(kind, params, kw, allowed, convert=None):
    """Sets params.<key> = value for each keyword (convert(key, value) first, if given); returns params."""
    check_keywords(kind, kw, allowed)
    for k, v in kw.items():
        setattr(params, k, convert(k, v) if convert else v)
    return params
