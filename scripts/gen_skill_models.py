#!/usr/bin/env python3
"""Writes the skillcell companion models models/Skillcell.*.NodeSet2.xml.

The models are written by the project (ARCHITECTURE.md, "The skill model"; the paper's
figure 4). This script is their source: edit it and run `python3 scripts/gen_skill_models.py`
from the repository root, then commit script and XML together. Namespace-0 NodeIds below
are facts of OPC 10000-3/-5/-10; everything else is ours.

Layering (RequiredModel):
  ns0 <- DI (the OPC Foundation's, models/opcfoundation/) <- Skills <- RoboticSkills,
         GripperSkills, ToolChangerSkills, CompositeSkills, MesSkills
"""
from __future__ import annotations

import os
from xml.sax.saxutils import escape

NS0_URI = "http://opcfoundation.org/UA/"
NS0_VERSION = "1.05.03"
NS0_DATE = "2023-12-15T00:00:00Z"
# The OPC Foundation's DI (OPC 10000-100): the oldest version with what the skills use
# (ParameterSet of TopologyElementType) that the Foundation's Robotics 1.02 also accepts.
DI_URI = "http://opcfoundation.org/UA/DI/"
DI_VERSION = "1.04.0"
DI_DATE = "2022-11-03T00:00:00Z"
VERSION = "1.00.0"
DATE = "2026-11-22T00:00:00Z"
BASE = "http://skillcell.dev/UA/"

# namespace-0 facts
HAS_SUBTYPE, HAS_COMPONENT, HAS_PROPERTY, ORGANIZES = "i=45", "i=47", "i=46", "i=35"
HAS_TYPEDEF, HAS_RULE, GENERATES_EVENT = "i=40", "i=37", "i=41"
MANDATORY, OPTIONAL = "i=78", "i=80"
BASE_OBJECT_TYPE, FOLDER_TYPE, OBJECTS_FOLDER = "i=58", "i=61", "i=85"
BASE_DATA_VARIABLE, PROPERTY_TYPE, BASE_ANALOG = "i=63", "i=68", "i=15318"
PROGRAM_STATE_MACHINE, PROGRAM_TRANSITION_EVENT = "i=2391", "i=2378"
DOUBLE, STRING, INT32, LOCALIZED_TEXT, ENUMERATION = "i=11", "i=12", "i=6", "i=21", "i=29"
BOOLEAN, UINT64, ARGUMENT, ARGUMENT_XML = "i=1", "i=9", "i=296", "i=297"
EU_INFORMATION, RANGE = "i=887", "i=884"
EU_XML, RANGE_XML = "i=888", "i=885"
FRAME_DT, FRAME_VT, FRAME_XML = "i=18814", "i=18791", "i=18859"
CART_VT, ORIENT_VT = "i=18774", "i=18781"
UNECE = "http://www.opcfoundation.org/UA/units/un/cefact"


def unit_id(code: str) -> int:
    """OPC 10000-8 5.6.3: the UNECE common code's characters, 8 bits each."""
    n = 0
    for ch in code:
        n = (n << 8) | ord(ch)
    return n


UNITS = {
    "m": ("MTR", "m", "metre"),
    "m/s": ("MTS", "m/s", "metre per second"),
    "m/s2": ("MSK", "m/s²", "metre per second squared"),
    "rad": ("C81", "rad", "radian"),
    "rad/s": ("2A", "rad/s", "radian per second"),
    "rad/s2": ("2B", "rad/s²", "radian per second squared"),
    "N": ("NEW", "N", "newton"),
    "kg": ("KGM", "kg", "kilogram"),
}


def eu_value(unit: str) -> str:
    code, symbol, name = UNITS[unit]
    return (
        "<Value><uax:ExtensionObject><uax:TypeId><uax:Identifier>" + EU_XML +
        "</uax:Identifier></uax:TypeId><uax:Body><uax:EUInformation>"
        f"<uax:NamespaceUri>{UNECE}</uax:NamespaceUri><uax:UnitId>{unit_id(code)}</uax:UnitId>"
        f"<uax:DisplayName><uax:Text>{escape(symbol)}</uax:Text></uax:DisplayName>"
        f"<uax:Description><uax:Text>{escape(name)}</uax:Text></uax:Description>"
        "</uax:EUInformation></uax:Body></uax:ExtensionObject></Value>")


def range_value(low: float, high: float) -> str:
    return (
        "<Value><uax:ExtensionObject><uax:TypeId><uax:Identifier>" + RANGE_XML +
        "</uax:Identifier></uax:TypeId><uax:Body><uax:Range>"
        f"<uax:Low>{low:g}</uax:Low><uax:High>{high:g}</uax:High>"
        "</uax:Range></uax:Body></uax:ExtensionObject></Value>")


ZERO_FRAME = (
    "<Value><uax:ExtensionObject><uax:TypeId><uax:Identifier>" + FRAME_XML +
    "</uax:Identifier></uax:TypeId><uax:Body><uax:ThreeDFrame>"
    "<uax:CartesianCoordinates><uax:X>0</uax:X><uax:Y>0</uax:Y><uax:Z>0</uax:Z>"
    "</uax:CartesianCoordinates>"
    "<uax:Orientation><uax:A>0</uax:A><uax:B>0</uax:B><uax:C>0</uax:C></uax:Orientation>"
    "</uax:ThreeDFrame></uax:Body></uax:ExtensionObject></Value>")

# symbol -> (namespace uri, numeric id), filled as the models are written
SYMBOLS: dict[str, tuple[str, int]] = {}


class Model:
    def __init__(self, key: str, title: str, requires: list["Model"], uri: str | None = None,
                 version: str = VERSION, date: str = DATE):
        self.key = key
        self.uri = uri or f"{BASE}{key}/"
        self.version, self.date = version, date
        self.external = uri is not None  # another organisation's model: required, not written
        self.title = title
        self.requires = requires
        # own namespace first, then every namespace of the required models
        self.uris = [self.uri]
        for r in requires:
            for u in r.uris:
                if u not in self.uris:
                    self.uris.append(u)
        self.nodes: list[str] = []
        self.next_type = 1001
        self.next_instance = 5001
        self.next_datatype = 3001
        # skill type symbol -> list of parameter specs (inherited ones included)
        self.params: dict[str, list[dict]] = {}
        self.types: list[tuple] = []  # (symbol, name, base, abstract, description)
        self.instances: list[str] = []  # doc lines for non-parameter instance declarations
        self.datatypes: list[str] = []  # doc lines for data types
        self.intro = ""

    # --- ids ---------------------------------------------------------------------------
    def nid(self, sym_or_id: str) -> str:
        if sym_or_id.startswith("i="):
            return sym_or_id
        uri, n = SYMBOLS[sym_or_id]
        return f"ns={self.uris.index(uri) + 1};i={n}"

    def qn(self, name: str, uri: str | None = None) -> str:
        return f"{self.uris.index(uri or self.uri) + 1}:{name}"

    def new_id(self, sym: str, kind: str) -> str:
        attr = {"type": "next_type", "inst": "next_instance", "dt": "next_datatype"}[kind]
        n = getattr(self, attr)
        setattr(self, attr, n + 1)
        SYMBOLS[sym] = (self.uri, n)
        return self.nid(sym)

    # --- nodes -------------------------------------------------------------------------
    def _node(self, tag: str, nid: str, bn: str, name: str, attrs: str, refs: list[tuple],
              desc: str = "", extra: str = "") -> None:
        out = [f'  <{tag} NodeId="{nid}" BrowseName="{bn}"{attrs}>',
               f"    <DisplayName>{escape(name)}</DisplayName>"]
        if desc:
            out.append(f"    <Description>{escape(desc)}</Description>")
        out.append("    <References>")
        for ref_type, target, forward in refs:
            fw = "" if forward else ' IsForward="false"'
            out.append(f'      <Reference ReferenceType="{ref_type}"{fw}>{target}</Reference>')
        out.append("    </References>")
        if extra:
            out.append("    " + extra)
        out.append(f"  </{tag}>")
        self.nodes.append("\n".join(out))

    def object_type(self, sym: str, name: str, base: str, abstract: bool, desc: str,
                    events: list[str] | None = None) -> str:
        nid = self.new_id(sym, "type")
        self.types.append((sym, name, base, abstract, desc))
        refs = [(HAS_SUBTYPE, self.nid(base), False)]
        refs += [(GENERATES_EVENT, self.nid(e), True) for e in events or []]
        self._node("UAObjectType", nid, self.qn(name), name,
                   ' IsAbstract="true"' if abstract else "", refs, desc)
        return nid

    def obj(self, sym: str, name: str, parent: str, typedef: str, rule: str | None,
            ref: str = HAS_COMPONENT, desc: str = "", name_uri: str | None = None) -> str:
        nid = self.new_id(sym, "inst")
        rule_name = {MANDATORY: "Mandatory", OPTIONAL: "Optional"}.get(rule or "", "")
        self.instances.append((parent, f"`{name}` ({rule_name or 'object'})"
                               + (f": {desc}" if desc else "")))
        parent_id = self.nid(parent)
        refs = [(HAS_TYPEDEF, self.nid(typedef), True)]
        if rule:
            refs.append((HAS_RULE, rule, True))
        refs.append((ref, parent_id, False))
        self._node("UAObject", nid, self.qn(name, name_uri), name,
                   f' ParentNodeId="{parent_id}"', refs, desc)
        return nid

    def var(self, sym: str, name: str, parent: str, datatype: str, typedef: str,
            rule: str | None, ref: str = HAS_COMPONENT, value: str = "", rank: int = -1,
            access: int = 1, desc: str = "", name_uri: str | None = None,
            bn_ns0: bool = False) -> str:
        nid = self.new_id(sym, "inst")
        if parent in SYMBOLS and SYMBOLS[parent][0] == self.uri and "." not in parent:
            rule_name = {MANDATORY: "Mandatory", OPTIONAL: "Optional"}.get(rule or "", "")
            self.instances.append((parent, f"`{name}` (property, {rule_name})"))
        parent_id = self.nid(parent)
        refs = [(HAS_TYPEDEF, self.nid(typedef), True)]
        if rule:
            refs.append((HAS_RULE, rule, True))
        refs.append((ref, parent_id, False))
        attrs = f' ParentNodeId="{parent_id}" DataType="{self.nid(datatype)}"'
        if rank != -1:
            attrs += f' ValueRank="{rank}"'
            if rank == 1:
                attrs += ' ArrayDimensions="0"'
        if access != 1:
            attrs += f' AccessLevel="{access}" UserAccessLevel="{access}"'
        bn = name if bn_ns0 else self.qn(name, name_uri)
        self._node("UAVariable", nid, bn, name, attrs, refs, desc, value)
        return nid

    def method(self, sym: str, name: str, parent: str, rule: str, desc: str,
               inputs: list[tuple[str, str, str]], outputs: list[tuple[str, str, str]]) -> str:
        """A method with its InputArguments/OutputArguments properties; each argument is
        (name, data type, description)."""
        nid = self.new_id(sym, "inst")
        self.instances.append((parent, f"`{name}()` (method): {desc}"))
        parent_id = self.nid(parent)
        self._node("UAMethod", nid, self.qn(name), name, f' ParentNodeId="{parent_id}"',
                   [(HAS_RULE, rule, True), (HAS_COMPONENT, parent_id, False)], desc)
        for prop_name, args in (("InputArguments", inputs), ("OutputArguments", outputs)):
            if not args:
                continue
            body = ["<Value>", "      <uax:ListOfExtensionObject>"]
            for arg_name, datatype, arg_desc in args:
                body += ["        <uax:ExtensionObject>",
                         f"          <uax:TypeId><uax:Identifier>{ARGUMENT_XML}</uax:Identifier>"
                         "</uax:TypeId>",
                         "          <uax:Body>",
                         "            <uax:Argument>",
                         f"              <uax:Name>{escape(arg_name)}</uax:Name>",
                         f"              <uax:DataType><uax:Identifier>{datatype}</uax:Identifier>"
                         "</uax:DataType>",
                         "              <uax:ValueRank>-1</uax:ValueRank>",
                         "              <uax:ArrayDimensions />",
                         f"              <uax:Description><uax:Text>{escape(arg_desc)}</uax:Text>"
                         "</uax:Description>",
                         "            </uax:Argument>",
                         "          </uax:Body>",
                         "        </uax:ExtensionObject>"]
            body += ["      </uax:ListOfExtensionObject>", "    </Value>"]
            self.var(f"{sym}.{prop_name}", prop_name, sym, ARGUMENT, PROPERTY_TYPE, MANDATORY,
                     HAS_PROPERTY, "\n".join(body), rank=1, bn_ns0=True)
        return nid

    def prop(self, sym: str, name: str, parent: str, datatype: str, value: str,
             rule: str | None = MANDATORY, rank: int = -1) -> str:
        return self.var(sym, name, parent, datatype, PROPERTY_TYPE, rule, HAS_PROPERTY, value,
                        rank, bn_ns0=True)

    # --- skills ------------------------------------------------------------------------
    def skill_type(self, sym: str, name: str, base: str, abstract: bool, desc: str,
                   params: list[dict]) -> None:
        """A skill type whose ParameterSet declares the inherited parameters and `params`.

        Every subtype repeats the whole ParameterSet: a subtype's declaration replaces its
        supertype's one with the same browse name (OPC 10000-3 6.3.3), so an instance of
        the subtype gets all of them.
        """
        self.object_type(sym, name, base, abstract, desc)
        inherited = next((p for m in [self] + all_models() for s, p in m.params.items()
                          if s == base), [])
        all_params = inherited + params
        self.params[sym] = all_params
        di = MODELS["DI"].uri
        self.obj(f"{sym}.ParameterSet", "ParameterSet", sym, BASE_OBJECT_TYPE, MANDATORY,
                 desc="The skill's parameters, written before Start.", name_uri=di)
        for p in all_params:
            self.parameter(f"{sym}.ParameterSet", p)

    def parameter(self, parent: str, p: dict) -> None:
        name, kind = p["name"], p["kind"]
        sym = f"{parent}.{name}"
        uri = p["uri"]
        access = 1 if p.get("readonly") else 3
        desc = p.get("desc", "")
        if kind == "frame":
            self.var(sym, name, parent, FRAME_DT, FRAME_VT, MANDATORY, value=ZERO_FRAME,
                     access=access, desc=desc, name_uri=uri)
            self.var(f"{sym}.CartesianCoordinates", "CartesianCoordinates", sym, "i=18810",
                     CART_VT, MANDATORY, bn_ns0=True)
            self.prop(f"{sym}.CartesianCoordinates.LengthUnit", "LengthUnit",
                      f"{sym}.CartesianCoordinates", EU_INFORMATION, eu_value("m"))
            self.var(f"{sym}.Orientation", "Orientation", sym, "i=18812", ORIENT_VT, MANDATORY,
                     bn_ns0=True)
            self.prop(f"{sym}.Orientation.AngleUnit", "AngleUnit", f"{sym}.Orientation",
                      EU_INFORMATION, eu_value("rad"))
        elif kind == "double":
            rank = p.get("rank", -1)
            value = "" if rank == 1 else "<Value><uax:Double>0</uax:Double></Value>"
            self.var(sym, name, parent, DOUBLE, BASE_ANALOG, MANDATORY, value=value,
                     rank=rank, access=access, desc=desc, name_uri=uri)
            self.prop(f"{sym}.EngineeringUnits", "EngineeringUnits", sym, EU_INFORMATION,
                      eu_value(p["unit"]))
            if "range" in p:
                self.prop(f"{sym}.EURange", "EURange", sym, RANGE, range_value(*p["range"]),
                          rule=OPTIONAL)
        elif kind == "ranges":
            # Range is no Number, so not an analog item: a data variable with units.
            self.var(sym, name, parent, RANGE, BASE_DATA_VARIABLE, MANDATORY, rank=1,
                     access=access, desc=desc, name_uri=uri)
            self.prop(f"{sym}.EngineeringUnits", "EngineeringUnits", sym, EU_INFORMATION,
                      eu_value(p["unit"]))
        elif kind == "string":
            self.var(sym, name, parent, STRING, BASE_DATA_VARIABLE, MANDATORY,
                     value="<Value><uax:String></uax:String></Value>", access=access,
                     desc=desc, name_uri=uri)
        elif kind == "enum":
            self.var(sym, name, parent, p["datatype"], BASE_DATA_VARIABLE, MANDATORY,
                     value=f"<Value><uax:Int32>{p.get('default', 0)}</uax:Int32></Value>",
                     access=access, desc=desc, name_uri=uri)
        else:
            raise ValueError(kind)

    def param(self, name: str, kind: str, **kw) -> dict:
        return {"name": name, "kind": kind, "uri": self.uri, **kw}

    def enum_type(self, sym: str, name: str, desc: str, values: list[str]) -> None:
        nid = self.new_id(sym, "dt")
        strings = "".join(f"<uax:LocalizedText><uax:Text>{v}</uax:Text></uax:LocalizedText>"
                          for v in values)
        fields = "".join(f'<Field Name="{v}" Value="{i}"/>' for i, v in enumerate(values))
        self.datatypes.append(f"- `{name}` (Enumeration, `ns=1;i={SYMBOLS[sym][1]}`): " +
                              ", ".join(f"{v} ({i})" for i, v in enumerate(values)) +
                              f"; EnumStrings and an EnumDefinition. {desc}")
        self.nodes.append("\n".join([
            f'  <UADataType NodeId="{nid}" BrowseName="{self.qn(name)}">',
            f"    <DisplayName>{name}</DisplayName>",
            f"    <Description>{escape(desc)}</Description>",
            "    <References>",
            f'      <Reference ReferenceType="{HAS_SUBTYPE}" IsForward="false">{ENUMERATION}'
            "</Reference>",
            "    </References>",
            f'    <Definition Name="{self.qn(name)}">{fields}</Definition>',
            f"  </UADataType>"]))
        self.var(f"{sym}.EnumStrings", "EnumStrings", sym, LOCALIZED_TEXT, PROPERTY_TYPE, None,
                 HAS_PROPERTY, f"<Value><uax:ListOfLocalizedText>{strings}"
                 "</uax:ListOfLocalizedText></Value>", rank=1, bn_ns0=True)
        # EnumStrings of a data type is a fixed-size array
        self.nodes[-1] = self.nodes[-1].replace('ArrayDimensions="0"',
                                                f'ArrayDimensions="{len(values)}"')

    # --- output ------------------------------------------------------------------------
    def xml(self) -> str:
        req = [f'      <RequiredModel ModelUri="{NS0_URI}" Version="{NS0_VERSION}" '
               f'PublicationDate="{NS0_DATE}"/>']
        req += [f'      <RequiredModel ModelUri="{r.uri}" Version="{r.version}" '
                f'PublicationDate="{r.date}"/>' for r in self.requires]
        uris = "\n".join(f"    <Uri>{u}</Uri>" for u in self.uris)
        return "\n".join([
            '<?xml version="1.0" encoding="utf-8"?>',
            "<!--",
            f"  skillcell companion model: {self.title}.",
            "  Written for skillcell (see docs/models/); generated by scripts/gen_skill_models.py,",
            "  edit that script, not this file.",
            "-->",
            '<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd"',
            '           xmlns:uax="http://opcfoundation.org/UA/2008/02/Types.xsd"',
            f'           LastModified="{DATE}">',
            "  <NamespaceUris>", uris, "  </NamespaceUris>",
            "  <Models>",
            f'    <Model ModelUri="{self.uri}" Version="{VERSION}" PublicationDate="{DATE}">',
            *req,
            "    </Model>",
            "  </Models>",
            *self.nodes,
            "</UANodeSet>", ""])


MODELS: dict[str, Model] = {}


def all_models() -> list[Model]:
    return list(MODELS.values())


def add(key: str, title: str, requires: list[str]) -> Model:
    m = Model(key, title, [MODELS[r] for r in requires])
    MODELS[key] = m
    return m


def build() -> None:
    # --- DI: the OPC Foundation's own (models/opcfoundation/Opc.Ua.Di.NodeSet2.xml) --------
    MODELS["DI"] = Model("DI", "Devices (OPC 10000-100)", [], uri=DI_URI, version=DI_VERSION,
                         date=DI_DATE)

    # --- Skills ------------------------------------------------------------------------
    sk = add("Skills", "Skills (SkillType and its transition event)", ["DI"])
    sk.intro = ("The generic skill (paper section VI.A; ARCHITECTURE.md, \"The skill model\"): a "
                "skill object is a ProgramStateMachineType with the states Halted, Ready, "
                "Running, Suspended, the methods Start, Suspend, Resume, Halt, Reset, and its "
                "parameters in a DI `ParameterSet`. Every state change raises a "
                "`SkillTransitionEventType` event (FromState, ToState, Transition).")
    sk.object_type("SkillTransitionEventType", "SkillTransitionEventType",
                   PROGRAM_TRANSITION_EVENT, False,
                   "Sent by a skill on every state change (FromState, ToState, Transition).")
    sk.object_type("SkillType", "SkillType", PROGRAM_STATE_MACHINE, True,
                   "A skill: a program state machine (Halted, Ready, Running, Suspended) "
                   "with its parameters in ParameterSet.",
                   events=["SkillTransitionEventType"])
    sk.obj("SkillType.ParameterSet", "ParameterSet", "SkillType", BASE_OBJECT_TYPE, MANDATORY,
           desc="The skill's parameters, written before Start.", name_uri=MODELS["DI"].uri)
    sk.params["SkillType"] = []
    # Reservation with fencing (docs/skills.md, "Reservation").
    sk.object_type("ReservationType", "ReservationType", BASE_OBJECT_TYPE, False,
                   "Who may drive the component's skills: while a holder has reserved it, "
                   "parameter writes and the skills' methods are accepted only from sessions "
                   "that present its current fencing token (Reserve or Use); every grant issues "
                   "a greater token, so a holder that lost the reservation is refused.")
    sk.var("ReservationType.Holder", "Holder", "ReservationType", STRING, BASE_DATA_VARIABLE,
           MANDATORY, desc="Who holds the reservation; empty when the component is free.")
    sk.var("ReservationType.FencingToken", "FencingToken", "ReservationType", UINT64,
           BASE_DATA_VARIABLE, MANDATORY,
           desc="The current token; 0 when free. Tokens only grow, across restarts too.")
    sk.method("ReservationType.Reserve", "Reserve", "ReservationType", MANDATORY,
              "Reserve the component for Holder, or take it over (Takeover) from another "
              "holder; grants a new token and binds the calling session to it. "
              "Bad_ResourceUnavailable while another holder has it and Takeover is false.",
              [("Holder", STRING, "who reserves (an MES and its order)"),
               ("Takeover", BOOLEAN, "take it from another holder (a failover)")],
              [("FencingToken", UINT64, "the token writes and methods are held to")])
    sk.method("ReservationType.Use", "Use", "ReservationType", MANDATORY,
              "Bind the calling session to the current token. Bad_InvalidArgument for a "
              "token that is not the current one (a stale holder).",
              [("FencingToken", UINT64, "the token Reserve granted")], [])
    sk.method("ReservationType.Release", "Release", "ReservationType", MANDATORY,
              "Free the component. Bad_InvalidArgument for a token that is not the current one.",
              [("FencingToken", UINT64, "the token Reserve granted")], [])

    # --- Robotic skills ----------------------------------------------------------------
    rs = add("RoboticSkills", "Robotic skills (move skills)", ["DI", "Skills"])
    rs.intro = ("Move skills of a manipulator. Linear moves limit the Cartesian speed of the tool "
                "centre point (m/s, m/s²); point-to-point moves are interpolated in joint "
                "space and limit joint speed (rad/s, rad/s²).")
    rs.skill_type("MoveSkillType", "MoveSkillType", "SkillType", True,
                  "Moves a manipulator.", [
                      rs.param("ToolFrame", "frame",
                               desc="Tool centre point relative to the flange."),
                      rs.param("Reach", "double", unit="m", range=(0, 100), readonly=True,
                               desc="How far the manipulator reaches: no flange position "
                                    "farther than this from ReachCentre can be reached "
                                    "(0: not published). What an MES checks a target "
                                    "against before it chooses the manipulator."),
                      rs.param("ReachCentre", "frame", readonly=True,
                               desc="The point Reach is measured from (the shoulder), in "
                                    "the cell's frame; its orientation is not used.")])
    lin = [rs.param("MaxVelocity", "double", unit="m/s", range=(0, 2),
                    desc="Cartesian speed limit of the tool centre point."),
           rs.param("MaxAcceleration", "double", unit="m/s2", range=(0, 10))]
    ptp = [rs.param("MaxVelocity", "double", unit="rad/s", range=(0, 3.2),
                    desc="Joint speed limit."),
           rs.param("MaxAcceleration", "double", unit="rad/s2", range=(0, 40))]
    rs.skill_type("LinearMoveSkillType", "LinearMoveSkillType", "MoveSkillType", True,
                  "A move along a straight line of the tool centre point.", lin)
    rs.skill_type("PtpMoveSkillType", "PtpMoveSkillType", "MoveSkillType", True,
                  "A point-to-point move, interpolated in joint space.", ptp)
    target = [rs.param("TargetPosition", "frame", desc="Target pose of the tool centre point."),
              rs.param("AxisBounds", "ranges", unit="rad",
                       desc="Per joint, the range the solution must lie in.")]
    joints = [rs.param("TargetJointPosition", "double", rank=1, unit="rad",
                       desc="Target position of every joint.")]
    rs.skill_type("CartesianLinearMoveSkillType", "CartesianLinearMoveSkillType",
                  "LinearMoveSkillType", False, "Linear move to a Cartesian pose.", target)
    rs.skill_type("CartesianPtpMoveSkillType", "CartesianPtpMoveSkillType",
                  "PtpMoveSkillType", False, "Point-to-point move to a Cartesian pose.", target)
    rs.skill_type("JointLinearMoveSkillType", "JointLinearMoveSkillType",
                  "LinearMoveSkillType", False, "Linear move to joint positions.", joints)
    rs.skill_type("JointPtpMoveSkillType", "JointPtpMoveSkillType", "PtpMoveSkillType", False,
                  "Point-to-point move to joint positions.", joints)
    rs.skill_type("CartesianForceLimitedLinearMoveSkillType",
                  "CartesianForceLimitedLinearMoveSkillType", "CartesianLinearMoveSkillType",
                  False,
                  "Linear move to a Cartesian pose that stops, Halted with the force in its "
                  "reason, where the tool meets more than ForceLimit (an insertion). Offered by "
                  "arms that measure force.", [
                      rs.param("ForceLimit", "double", unit="N", range=(0, 500),
                               desc="The contact force above which the move stops.")])

    # --- Gripper skills ----------------------------------------------------------------
    gs = add("GripperSkills", "Gripper skills (grasp, release, move gripper)", ["DI", "Skills"])
    gs.intro = ("Skills of a gripper at one grip point (paper section VI.C). The grip point is "
                "described by two read-only parameters: its offset from the tool mounting "
                "plate (`GripPointOffset`, a 3D frame) and its type (`GripPointType`: "
                "PARALLEL, VACUUM or MULTIFINGER); what it can hold by two more: "
                "`MaxPayload` (kg) and `MaxGripWidth` (m, 0: not limited by width); the "
                "robot that carries it by `RobotUri`. A "
                "gripper with several grip points offers one skill instance per grip point.")
    gs.enum_type("GripPointTypeEnumeration", "GripPointTypeEnumeration",
                 "How a gripper holds an object.", ["PARALLEL", "VACUUM", "MULTIFINGER"])
    grip = [gs.param("GripPointOffset", "frame", readonly=True,
                     desc="Grip point relative to the tool mounting plate."),
            gs.param("GripPointType", "enum", datatype="GripPointTypeEnumeration",
                     readonly=True, desc="PARALLEL, VACUUM or MULTIFINGER."),
            gs.param("MaxPayload", "double", unit="kg", range=(0, 1000), readonly=True,
                     desc="The heaviest object it holds at this grip point."),
            gs.param("MaxGripWidth", "double", unit="m", range=(0, 10), readonly=True,
                     desc="The widest object it grips across (a parallel gripper's stroke); "
                          "0 when width does not limit it (a vacuum gripper)."),
            gs.param("RobotUri", "string", readonly=True,
                     desc="Application URI of the robot whose flange carries the gripper (its "
                          "tool changer knows it); empty when not known.")]
    gs.skill_type("GripperSkillType", "GripperSkillType", "SkillType", True,
                  "A skill of a gripper at one grip point.", grip)
    gs.skill_type("GraspGripperSkillType", "GraspGripperSkillType", "GripperSkillType", False,
                  "Attaches the object at the grip point; Halted if the grasp failed.", [])
    gs.skill_type("ReleaseGripperSkillType", "ReleaseGripperSkillType", "GripperSkillType",
                  False, "Lets go of the held object.", [])
    gs.skill_type("MoveGripperSkillType", "MoveGripperSkillType", "GripperSkillType", False,
                  "Moves the fingers to a width with a force limit.", [
                      gs.param("Width", "double", unit="m", range=(0, 0.3)),
                      gs.param("Force", "double", unit="N", range=(0, 500))])

    # --- Tool changer skills -----------------------------------------------------------
    ts = add("ToolChangerSkills", "Tool-changer skills (attach, detach, change tool)",
             ["DI", "Skills"])
    ts.intro = ("Skills of a tool changer mounted on a motion component (paper section VI.C). "
                "They move that component through its Cartesian move skill, whose endpoint "
                "they expose read-only. `ToolChangerSkillType` is an abstract base added by "
                "skillcell to hold the common parameters.")
    common = [ts.param("ToolPosition", "frame",
                       desc="Absolute pose where the tool is picked up or placed."),
              ts.param("MoveSkillControllerEndpoint", "string", readonly=True,
                       desc="Endpoint URL of the move skill the tool changer is mounted on."),
              ts.param("RobotUri", "string", readonly=True,
                       desc="Application URI of the robot the tool changer is mounted on; "
                            "empty when not known.")]
    ts.skill_type("ToolChangerSkillType", "ToolChangerSkillType", "SkillType", True,
                  "A skill of a tool changer mounted on a motion component.", common)
    app = [ts.param("ToolAppUri", "string",
                    desc="Application URI of the tool, to detect it once attached.")]
    ts.skill_type("AttachToolSkillType", "AttachToolSkillType", "ToolChangerSkillType", False,
                  "Attaches the tool at ToolPosition.", app)
    ts.skill_type("DetachToolSkillType", "DetachToolSkillType", "ToolChangerSkillType", False,
                  "Places the attached tool (if any) at ToolPosition.", [])
    ts.skill_type("ChangeToolSkillType", "ChangeToolSkillType", "ToolChangerSkillType", False,
                  "Detaches the current tool, then attaches the one at ToolPosition.", app)

    # --- Composite skills --------------------------------------------------------------
    cs = add("CompositeSkills", "Composite skills (pick and place, place a terminal block)", ["DI", "Skills"])
    cs.intro = ("Skills composed of other components' skills (paper section VI.B): pick and "
                "place uses a tool's gripper skills and a move skill, both named by endpoint.")
    cs.skill_type("PickAndPlaceSkillType", "PickAndPlaceSkillType", "SkillType", False,
                  "Moves the object ObjectId to PlacePosition using a tool and a move skill.", [
                      cs.param("ObjectId", "string"),
                      cs.param("ToolSkillControllerEndpoint", "string"),
                      cs.param("MoveSkillControllerEndpoint", "string"),
                      cs.param("PlacePosition", "frame",
                               desc="Target pose of the object.")])
    cs.skill_type("PlaceTerminalBlockSkillType", "PlaceTerminalBlockSkillType", "SkillType",
                  False,
                  "Places the terminal block ObjectId on the DIN rail RailId at Position: "
                  "hooks it over the rail's upper edge, rotates it down until it snaps, "
                  "releases it and checks that it is mounted.", [
                      cs.param("ObjectId", "string"),
                      cs.param("RailId", "string", desc="The rail, as the world model names it."),
                      cs.param("Position", "double", unit="m", range=(-1, 10),
                               desc="The block's centre along the rail from its start; "
                                    "negative: side by side after the last block on the rail."),
                      cs.param("ToolSkillControllerEndpoint", "string"),
                      cs.param("MoveSkillControllerEndpoint", "string")])

    cs.skill_type("InsertFuseSkillType", "InsertFuseSkillType", "SkillType", False,
                  "Picks the blade fuse ObjectId from the top and inserts it into the fuse "
                  "slot SlotId along the slot's axis with the robot's force-limited linear "
                  "move; releases it and checks that it is seated. Stops with the force in "
                  "its reason where the fuse meets more than ForceLimit (a misaligned slot).", [
                      cs.param("ObjectId", "string"),
                      cs.param("SlotId", "string", desc="The slot, as the world model names it."),
                      cs.param("ForceLimit", "double", unit="N", range=(0, 500),
                               desc="The contact force above which the insertion stops."),
                      cs.param("ToolSkillControllerEndpoint", "string"),
                      cs.param("MoveSkillControllerEndpoint", "string")])

    # --- MES skills --------------------------------------------------------------------
    ms = add("MesSkills", "MES skills (execute process)", ["DI", "Skills"])
    ms.intro = ("The skill a manufacturing execution system offers: execute a process "
                "described in the knowledge base (paper section VII).")
    ms.skill_type("ExecuteProcessSkillType", "ExecuteProcessSkillType", "SkillType", False,
                  "Executes the manufacturing process described at ProcessIri.", [
                      ms.param("ProcessIri", "string",
                               desc="IRI of the process description in the knowledge base.")])


PARAM_DOC = {
    "frame": "3DFrame (3DFrameType): X, Y, Z in m (LengthUnit MTR), A, B, C in rad "
             "(AngleUnit C81)",
    "string": "String",
    "ranges": "Range[] (BaseDataVariableType with an EngineeringUnits property)",
}


def param_doc(p: dict) -> str:
    kind = p["kind"]
    if kind == "double":
        code, symbol, _ = UNITS[p["unit"]]
        text = ("Double[]" if p.get("rank", -1) == 1 else "Double") + \
            f" (BaseAnalogType), {symbol} ({code})"
        if "range" in p:
            text += f", EURange {p['range'][0]:g}..{p['range'][1]:g} (Optional, type default)"
    elif kind == "ranges":
        code, symbol, _ = UNITS[p["unit"]]
        text = PARAM_DOC[kind] + f", {symbol} ({code})"
    elif kind == "enum":
        text = p["datatype"]
    else:
        text = PARAM_DOC[kind]
    access = "read-only" if p.get("readonly") else "read/write"
    desc = f" {p['desc']}" if p.get("desc") else ""
    return f"`{p['name']}`: {text}; {access}.{desc}"


def docs(m: Model) -> str:
    req = ", ".join(["OPC UA namespace 0 (" + NS0_VERSION + ")"] +
                    [f"the OPC Foundation's {r.key} ({r.version}, `{r.uri}`)" if r.external
                     else f"[{r.key}]({r.key}.md)" for r in m.requires])
    out = [f"# {m.title}", "",
           f"Namespace `{m.uri}`, version {VERSION}, file "
           f"`models/Skillcell.{m.key}.NodeSet2.xml`. RequiredModels: {req}.", ""]
    if m.intro:
        out += [m.intro, ""]
    out += ["Written for skillcell (generated by `scripts/gen_skill_models.py`; edit that, "
            "then regenerate). NodeIds below are in this namespace.", ""]
    if m.datatypes:
        out += ["## Data types", ""] + m.datatypes + [""]
    if m.types:
        out += ["## Type tree", "", "```"]
        children: dict[str, list[tuple]] = {}
        for t in m.types:
            children.setdefault(t[2], []).append(t)

        def walk(sym: str, depth: int) -> None:
            for t in children.get(sym, []):
                abstract = " (abstract)" if t[3] else ""
                out.append("  " * depth + f"└─ {t[1]}{abstract}  i={SYMBOLS[t[0]][1]}")
                walk(t[0], depth + 1)

        for base in dict.fromkeys(t[2] for t in m.types if t[2] not in
                                  {x[0] for x in m.types}):
            owner = next((k for k, x in MODELS.items() if SYMBOLS.get(base, ("",))[0] == x.uri),
                         "")
            label = f"{base} ({owner}, i={SYMBOLS[base][1]})" if owner else {
                BASE_OBJECT_TYPE: "BaseObjectType (i=58)",
                PROGRAM_STATE_MACHINE: "ProgramStateMachineType (i=2391)",
                PROGRAM_TRANSITION_EVENT: "ProgramTransitionEventType (i=2378)"}.get(base, base)
            out.append(label)
            walk(base, 1)
        out += ["```", ""]
        out += ["## Types", ""]
        for sym, name, base, abstract, desc in m.types:
            out.append(f"### {name}")
            out += ["", desc, ""]
            for parent, line in m.instances:
                if parent == sym and not (sym in m.params and "ParameterSet" in line):
                    out.append(f"- {line}")
            if sym in m.params:
                out.append("- `ParameterSet` (DI, Mandatory) with these Mandatory "
                           "parameters (inherited ones repeated):" if m.params[sym] else
                           "- `ParameterSet` (DI, Mandatory): no parameters of its own.")
                for p in m.params[sym]:
                    out.append(f"  - {param_doc(p)}")
            out.append("")
    return "\n".join(out).rstrip() + "\n"


def main() -> None:
    build()
    doc_root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "models")
    os.makedirs(doc_root, exist_ok=True)
    written = {key: m for key, m in MODELS.items() if not m.external}
    for key, m in written.items():
        with open(os.path.join(doc_root, f"{key}.md"), "w", encoding="utf-8") as f:
            f.write(docs(m))
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models")
    for key, m in written.items():
        path = os.path.join(root, f"Skillcell.{key}.NodeSet2.xml")
        with open(path, "w", encoding="utf-8") as f:
            f.write(m.xml())
        print(path)


if __name__ == "__main__":
    main()
