// node-opcua writes its warnings and debug traces with console.log (some of
// them while being required). Send console.log/info/debug to stderr so that
// stdout carries only the lines the scripts print on purpose (READY line,
// summary, JSON). Require this module before node-opcua.
"use strict";

const { format } = require("util");

const toStderr = (...args) => {
    process.stderr.write(format(...args) + "\n");
};
console.log = toStderr;
console.info = toStderr;
console.debug = toStderr;
