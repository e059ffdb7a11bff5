#pragma once
// NodeSet2 -> OWL 2: one ontology per NodeSet (OPC 10000-6 Annex F in, Turtle out).
//
// The mapping (docs/knowledge_base.md has the reasons):
//   - the ontology's IRI is the NodeSet's model URI; it imports the models the NodeSet
//     requires (RequiredModel) and skillcell's core OPC UA ontology;
//   - ObjectTypes, VariableTypes and DataTypes are owl:Class, HasSubtype between them
//     rdfs:subClassOf; ReferenceTypes are owl:ObjectProperty, HasSubtype between them
//     rdfs:subPropertyOf (Symmetric ones owl:SymmetricProperty);
//   - Objects, Variables, Methods and Views are owl:NamedIndividual, typed by their
//     HasTypeDefinition;
//   - every reference is an assertion of its reference type's property (inverse references
//     are turned around), so SPARQL property paths follow the address space;
//   - attributes are the core ontology's data properties (opc:browseName, opc:nodeId,
//     opc:isAbstract, opc:valueRank, opc:dataType, rdfs:label, rdfs:comment), a variable's
//     simple scalar value is opc:value, and its EngineeringUnits and EURange properties
//     become opc:engineeringUnits, opc:euRangeLow and opc:euRangeHigh on the variable itself
//     (what a query about a skill parameter's unit or limits needs).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "kb/expected.hpp"
#include "kb/rdf/triple.hpp"
#include "kb/rdf/turtle.hpp"
#include "ua/address_space/address_space.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skillcell::kb::owl {

struct Ontology {
    std::string iri;                   // the model URI
    std::string version;               // the model's version, if given
    std::vector<std::string> imports;  // required models, then the core ontology
    std::vector<rdf::Triple> triples;  // the header (owl:Ontology, imports) included
    std::string source;                // the NodeSet it came from, for messages
};

/// Converts `parsed`, which was parsed against `known` (the address space with the models
/// loaded before it, used to name the types and reference types it points to).
[[nodiscard]] Expected<Ontology> nodeSetToOntology(const ua::AddressSpace& known,
                                                   const ua::ParsedNodeSet& parsed);

/// A NodeSet2 document and the name to use for it in messages.
struct NodeSetText {
    std::string name;
    std::string xml;
};

/// Converts NodeSets in order: each may require namespace 0 (loaded from the embedded base
/// NodeSet) and the ones before it. The base NodeSet's own ontology comes first when
/// `includeBase`. On error nothing is returned; the message names the file and line.
/// With `afterCompanionModels`, the embedded companion models are loaded first (not
/// converted), so that the files may require them too. Namespace 0's ontology includes the
/// nodes the OPC Foundation's models use beyond our subset (the closure) unless
/// `withClosure` is false.
[[nodiscard]] Expected<std::vector<Ontology>> convertNodeSets(const std::vector<NodeSetText>& files,
                                                              bool includeBase,
                                                              bool afterCompanionModels = false,
                                                              bool withClosure = true);

/// The embedded NodeSets (models/*.xml): namespace 0 and every companion model, in
/// dependency order, each as an ontology. Without `withFoundationModels`, only namespace 0
/// (our subset) and skillcell's skill models: what processes are written against, and a
/// quarter of the triples a reasoner would otherwise realize on every load.
[[nodiscard]] Expected<std::vector<Ontology>> embeddedModelOntologies(
    bool withFoundationModels = true);

/// The prefixes Turtle output uses (rdf, rdfs, owl, xsd, opc, ua and the companion models).
[[nodiscard]] std::vector<rdf::Prefix> standardPrefixes();

/// The ontology as Turtle (deterministic: the same NodeSet gives the same bytes).
[[nodiscard]] std::string toTurtle(const Ontology& ontology);

/// skillcell's core OPC UA ontology (models/owl/opcua-core.ttl, compiled in).
[[nodiscard]] std::string_view coreOntologyTurtle();

}  // namespace skillcell::kb::owl
