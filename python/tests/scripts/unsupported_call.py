def createScene(rootNode):
    body = rootNode.addChild("body")
    body.addObjet("MechanicalObject")
