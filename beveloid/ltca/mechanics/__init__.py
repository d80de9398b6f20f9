"""The contact mechanics, independent of gears: the Boussinesq half-space (``halfspace``), Hertz
(``hertz``), the tooth's plate compliance (``tooth_compliance``), the normal-contact complementarity
problem (``lcp``) and its compiled active-set solve (``kernel``), the argument checks (``checks``)."""

__all__ = ["checks", "halfspace", "hertz", "kernel", "lcp", "tooth_compliance"]
