"""builder layer of epuck_vrep_compat: the one place that makes a simulation from a scene and a
config (:func:`.build.build_simulation`), adds every robot family's extension, and derives every
random stream from the one seed by name (:mod:`.streams`)."""
