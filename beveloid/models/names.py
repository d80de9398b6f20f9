"""The names the import hook works with (a leaf module: the finder and the hook both read it)."""

#: the package whose glue modules the hook may serve
PACKAGE = "beveloid.generated"
#: the glue modules the hook may serve (the surface_* and layout_* modules of user models too)
GLUE = ("surface_models", "tca_kernels", "tca_kernels_scalar")
