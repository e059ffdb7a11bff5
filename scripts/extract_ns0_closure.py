#!/usr/bin/env python3
"""Writes the namespace-0 nodes that the OPC Foundation's companion NodeSets in
models/opcfoundation/ use and models/Opc.Ua.NodeSet2.Base.xml lacks, with what they need in
turn (supertypes, type definitions, data types, encodings, instance declarations), taken from
the OPC Foundation's Opc.Ua.NodeSet2.xml (MIT, its license header kept in the output).

References to nodes that are in neither file are dropped, so the two files together load on
their own. Usage:

  scripts/extract_ns0_closure.py FULL_NS0.xml > models/opcfoundation/Opc.Ua.NodeSet2.Closure.xml

FULL_NS0.xml: e.g. tests/interop/node_modules/node-opcua-nodesets/nodesets/Opc.Ua.NodeSet2.xml.
"""
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

UA = "http://opcfoundation.org/UA/2011/03/UANodeSet.xsd"
UAX = "http://opcfoundation.org/UA/2008/02/Types.xsd"
NS = "{" + UA + "}"
ROOT = Path(__file__).resolve().parent.parent
COMPANIONS = ["Opc.Ua.Di.NodeSet2.xml", "Opc.Ua.IA.NodeSet2.xml", "Opc.Ua.Robotics.NodeSet2.xml"]
CHILD_REFS = {"HasComponent", "HasProperty", "HasOrderedComponent", "i=47", "i=46", "i=49"}
TYPE_REFS = {"HasTypeDefinition", "HasModellingRule", "HasEncoding", "i=40", "i=37", "i=38"}


def ns0(value, aliases):
    value = aliases.get(value, value) if value else value
    return int(value[2:]) if value and re.fullmatch(r"i=\d+", value) else None


def aliases_of(root):
    return {a.get("Alias"): a.text for a in root.iter(NS + "Alias")}


def ns0_nodes(root):
    return {int(n.get("NodeId")[2:]): n for n in root
            if n.get("NodeId") and re.fullmatch(r"i=\d+", n.get("NodeId"))}


def used_ns0(root):
    """Every namespace-0 node a companion file names: attributes, references, fields, values."""
    aliases = aliases_of(root)
    out = set()
    for n in root:
        if not n.tag.replace(NS, "").startswith("UA"):
            continue
        out.add(ns0(n.get("DataType"), aliases))
        out.add(ns0(n.get("ParentNodeId"), aliases))
        for r in n.iter(NS + "Reference"):
            out.add(ns0(r.get("ReferenceType"), aliases))
            out.add(ns0(r.text.strip(), aliases))
        for f in n.iter(NS + "Field"):
            out.add(ns0(f.get("DataType"), aliases))
        for ident in n.iter("{" + UAX + "}Identifier"):
            out.add(ns0(ident.text.strip(), aliases))
    out.discard(None)
    return out


def needs(node, aliases):
    """What a node cannot be loaded (or instantiated) without."""
    tag = node.tag.replace(NS, "")
    out = {ns0(node.get("DataType"), aliases)}
    for r in node.iter(NS + "Reference"):
        rt, target = r.get("ReferenceType"), ns0(r.text.strip(), aliases)
        forward = r.get("IsForward", "true") != "false"
        out.add(ns0(rt, aliases))
        if target is None:
            continue
        if (rt in ("HasSubtype", "i=45") and not forward) or rt in TYPE_REFS:
            out.add(target)
        elif rt in CHILD_REFS and forward and (tag.endswith("Type") or node.get("ParentNodeId")):
            out.add(target)  # the instance declarations of a type, and theirs
    for f in node.iter(NS + "Field"):
        out.add(ns0(f.get("DataType"), aliases))
    out.discard(None)
    return out


def main():
    full = ET.parse(sys.argv[1]).getroot()
    aliases = aliases_of(full)
    nodes = ns0_nodes(full)
    base = set(ns0_nodes(ET.parse(ROOT / "models/Opc.Ua.NodeSet2.Base.xml").getroot()))
    wanted = set()
    for name in COMPANIONS:
        wanted |= used_ns0(ET.parse(ROOT / "models/opcfoundation" / name).getroot())
    chosen, todo = set(), sorted(wanted - base)
    while todo:
        i = todo.pop()
        if i in base or i in chosen:
            continue
        if i not in nodes:
            sys.exit(f"node i={i} is in neither namespace-0 file")
        chosen.add(i)
        todo.extend(needs(nodes[i], aliases))
    known = base | chosen

    ET.register_namespace("", UA)
    ET.register_namespace("uax", UAX)
    out = ET.Element(NS + "UANodeSet")
    alias_el = ET.SubElement(out, NS + "Aliases")
    for a in full.iter(NS + "Alias"):
        ET.SubElement(alias_el, NS + "Alias", {"Alias": a.get("Alias")}).text = a.text
    for i in sorted(chosen):
        node = nodes[i]
        refs = node.find(NS + "References")
        if refs is not None:
            for r in list(refs):
                target = ns0(r.text.strip(), aliases)
                if target is not None and target not in known:
                    refs.remove(r)
        for drop in ("Documentation", "Category"):
            for el in node.findall(NS + drop):
                node.remove(el)
        out.append(node)
    ET.indent(out, "  ")
    header = Path(sys.argv[1]).read_text(encoding="utf-8")
    license_text = header[header.index("<!--"):header.index("-->") + 3]
    sys.stdout.write('<?xml version="1.0" encoding="utf-8"?>\n' + license_text + "\n<!--\n"
                     "  The namespace-0 nodes that the OPC Foundation's DI, IA and Robotics "
                     "models use\n  beyond models/Opc.Ua.NodeSet2.Base.xml, from the OPC "
                     "Foundation's Opc.Ua.NodeSet2.xml.\n  Generated by "
                     "scripts/extract_ns0_closure.py; do not edit.\n-->\n")
    sys.stdout.write(ET.tostring(out, encoding="unicode") + "\n")


if __name__ == "__main__":
    main()
