// Interop: node-opcua, an independent implementation, loads our companion models
// (models/Skillcell.*.NodeSet2.xml) on top of its own namespace 0 and the OPC Foundation's
// DI, IA and Robotics as we ship them (models/opcfoundation/), instantiates every
// concrete skill type and checks what a skill client relies on: the ParameterSet with every
// parameter, engineering units, the 3D frame and the grip point enumeration.
// Usage: node load_skill_models.js MODELS_DIR
"use strict";
const path = require("path");
const assert = require("assert");
const { AddressSpace } = require("node-opcua-address-space");
const { generateAddressSpace } = require("node-opcua-address-space/nodeJS");
const { nodesets } = require("node-opcua-nodesets");

const foundation = ["Opc.Ua.Di", "Opc.Ua.IA", "Opc.Ua.Robotics"];
const order = ["Skills", "RoboticSkills", "GripperSkills", "ToolChangerSkills",
               "CompositeSkills", "MesSkills"];
const concrete = {
  RoboticSkills: ["CartesianLinearMoveSkillType", "CartesianPtpMoveSkillType",
                  "JointLinearMoveSkillType", "JointPtpMoveSkillType"],
  GripperSkills: ["GraspGripperSkillType", "ReleaseGripperSkillType", "MoveGripperSkillType"],
  ToolChangerSkills: ["AttachToolSkillType", "DetachToolSkillType", "ChangeToolSkillType"],
  CompositeSkills: ["PickAndPlaceSkillType"],
  MesSkills: ["ExecuteProcessSkillType"],
};
const uri = (key) => `http://skillcell.dev/UA/${key}/`;

(async () => {
  const dir = process.argv[2];
  const as = AddressSpace.create();
  await generateAddressSpace(
      as, [nodesets.standard,
           ...foundation.map((f) => path.join(dir, "opcfoundation", `${f}.NodeSet2.xml`)),
           ...order.map((k) => path.join(dir, `Skillcell.${k}.NodeSet2.xml`))]);
  const skillType = as.findObjectType("SkillType", as.getNamespaceIndex(uri("Skills")));
  assert(skillType, "SkillType");
  assert(skillType.isSubtypeOf(as.findObjectType("ProgramStateMachineType")));
  let n = 0;
  for (const [key, types] of Object.entries(concrete)) {
    const ns = as.getNamespaceIndex(uri(key));
    for (const name of types) {
      const type = as.findObjectType(name, ns);
      assert(type, name);
      assert(type.isSubtypeOf(skillType), `${name} is a SkillType`);
      const skill = type.instantiate({browseName: `${name}.${n++}`,
                                      organizedBy: as.rootFolder.objects});
      const params = skill.getComponentByName("ParameterSet");
      assert(params, `${name}: ParameterSet`);
      const names = params.getComponents().map((c) => c.browseName.name);
      assert(names.length > 0 || key === "MesSkills", `${name}: parameters`);
      for (const c of params.getComponents()) {
        const eu = c.getPropertyByName("EngineeringUnits");
        if (eu) {
          const v = eu.readValue().value.value;
          assert.strictEqual(v.namespaceUri, "http://www.opcfoundation.org/UA/units/un/cefact");
          assert(v.unitId > 0, `${name}/${c.browseName.name}: unit`);
        }
        if (c.dataType.value === 18814) {  // 3DFrame
          const frame = c.readValue().value.value;
          assert.strictEqual(frame.cartesianCoordinates.x, 0, `${name}/${c.browseName.name}`);
        }
      }
      console.log(`${name}: ${names.join(", ")}`);
    }
  }
  const grip = as.findDataType("GripPointTypeEnumeration",
                               as.getNamespaceIndex(uri("GripperSkills")));
  assert.deepStrictEqual(grip.getEnumDefinition().fields.map((f) => f.name),
                         ["PARALLEL", "VACUUM", "MULTIFINGER"]);
  as.dispose();
  console.log("ok");
})().catch((e) => {
  console.error("FAILED", e);
  process.exit(1);
});
