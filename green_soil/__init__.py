"""A layered soil from its Green's functions: the surface flexibility of a
horizontally layered viscoelastic half-space in the frequency-wavenumber
domain (`spectral`), its Hankel transform and footprint averages
(`greens`), footprint-to-footprint and footprint-to-point responses in the
frequency and time domains with a cache (`responses`). numpy and scipy
only; see docs/green-soil.md."""
