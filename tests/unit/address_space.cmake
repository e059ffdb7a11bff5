# unit tests of src/ua/address_space
