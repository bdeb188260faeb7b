// planted: a test folder mirroring no module (the tests_layout rule)
