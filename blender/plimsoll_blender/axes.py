# Plimsoll's axes (+y up, right-handed: the bundle's and the project's) against Blender's
# (+z up, right-handed). Blender's glTF importer converts with the same rotation, so a bundle's
# object-space points land where the importer puts the mesh.


def plimsoll_to_blender(p):
    """(x, y, z) with +y up -> Blender's (x, -z, y)."""
    return (p[0], -p[2], p[1])


def blender_to_plimsoll(p):
    """Blender's (x, y, z) with +z up -> (x, z, -y) with +y up."""
    return (p[0], p[2], -p[1])
