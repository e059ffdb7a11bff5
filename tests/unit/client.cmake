# unit tests of src/ua/client
