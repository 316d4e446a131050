//! Not implemented yet (see docs/validation-sph.md, "Not done"): this module is a
//! placeholder so the area layout is fixed; nothing is registered from it.
