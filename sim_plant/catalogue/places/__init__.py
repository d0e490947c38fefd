"""Our worlds, the places a body moves in: catalogue entries as a user's are
(:class:`~sim_plant.catalogue.base.WorldType`, one class a module). A body takes one by its
kind (``world = "duct"``, or a rig file's ``[world]`` table), its options from
``world_options``. The room and the furnished room are the differential body's own (its
``room_w_m``, ``obstacles``, ``route`` options)."""
