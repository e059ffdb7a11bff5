# unit tests of src/ua/server
