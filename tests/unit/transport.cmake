# unit tests of src/ua/transport
