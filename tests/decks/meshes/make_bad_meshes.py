#!/usr/bin/env python3
"""Write the broken Gmsh files of the bad-input decks (tests/decks/bad_msh_*.nml).

Each file is a variant of one valid MSH 4.1 ASCII mesh, a single unit cube
hexahedron (element tag 1) with eight nodes (tags 1..8) and no $Entities
(its cell goes to the region "default"). Run from the repository root:

    python3 tests/decks/meshes/make_bad_meshes.py

and commit the .msh files it writes next to itself.
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
COORDS = ["0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1"]


def mesh(coords=None, nodes_header="1 8 1 8", node_block="3 1 0 8",
         elements_header="1 1 1 1", element_block="3 1 5 1",
         elements=("1 1 2 3 4 5 6 7 8",), end_nodes="$EndNodes",
         end_elements="$EndElements", extra_before_nodes=()):
    coords = coords or COORDS
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", *extra_before_nodes,
             "$Nodes", nodes_header, node_block]
    lines += [str(i + 1) for i in range(len(coords))]
    lines += list(coords)
    if end_nodes:
        lines.append(end_nodes)
    lines += ["$Elements", elements_header, element_block, *elements]
    if end_elements:
        lines.append(end_elements)
    return "\n".join(lines) + "\n"


def with_coord(k, text):
    c = list(COORDS)
    c[k] = text
    return c


CASES = {
    # coordinates
    "coord_nan": mesh(coords=with_coord(2, "1 nan 0")),
    "coord_inf": mesh(coords=with_coord(4, "0 0 -Infinity")),
    "coord_1e400": mesh(coords=with_coord(1, "1e400 0 0")),
    "coord_garbage": mesh(coords=with_coord(6, "1 1 one")),
    "coord_two_numbers": mesh(coords=with_coord(3, "0 1")),
    "coord_huge": mesh(coords=with_coord(6, "1 1 1e35")),
    # structure
    "truncated_nodes": mesh().split("0 1 0\n")[0],
    "truncated_elements": mesh().rsplit("1 1 2 3", 1)[0],
    "no_end_nodes": mesh(end_nodes=None),
    "no_end_elements": mesh(end_elements=None),
    # counts in headers
    "nodes_too_many": mesh(nodes_header="1 2000000000 1 2000000000"),
    "nodes_negative": mesh(nodes_header="1 -8 1 8"),
    "nodes_not_integer": mesh(nodes_header="1 8.5 1 8"),
    "node_block_too_many": mesh(node_block="3 1 0 900000000000"),
    "node_blocks_too_many": mesh(nodes_header="123456789012 8 1 8"),
    "elements_too_many": mesh(elements_header="1 3000000000 1 1"),
    "elements_negative": mesh(element_block="3 1 5 -1"),
    "elements_not_integer": mesh(elements_header="1 one 1 1"),
    "physical_names_too_many": mesh(extra_before_nodes=("$PhysicalNames", "99999999", '3 1 "rock"',
                                                         "$EndPhysicalNames")),
    "entities_negative": mesh(extra_before_nodes=("$Entities", "0 0 -1 1", "$EndEntities")),
    # elements
    "unknown_node": mesh(elements=("1 1 2 3 4 5 6 7 42",)),
    "prism": mesh(element_block="3 1 6 1", elements=("1 1 2 3 5 6 7",)),
    "no_volume": mesh(element_block="2 1 3 1", elements=("1 1 2 3 4",)),
    # degenerate hexahedra: a collapsed top face, an inverted cell (top and
    # bottom swapped), all nodes at one point, a repeated node, a flat cell
    "hex_collapsed_face": mesh(coords=COORDS[:4] + ["0.5 0.5 1"] * 4),
    "hex_inverted": mesh(coords=COORDS[4:] + COORDS[:4]),
    "hex_one_point": mesh(coords=["2 3 4"] * 8),
    "hex_repeated_node": mesh(elements=("1 1 2 3 4 5 6 7 5",)),
    "hex_flat": mesh(coords=COORDS[:4] + ["0 0 0", "1 0 0", "1 1 0", "0 1 0"]),
}

if __name__ == "__main__":
    for name, text in CASES.items():
        with open(os.path.join(HERE, f"bad_{name}.msh"), "w") as out:
            out.write(text)
    with open(os.path.join(HERE, "empty.msh"), "w"):
        pass
    print(f"{len(CASES) + 1} files written to {HERE}")
