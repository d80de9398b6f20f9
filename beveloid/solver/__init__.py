"""The contact solver: one core (:mod:`.core`) and its two backends (:mod:`.backends`)."""
