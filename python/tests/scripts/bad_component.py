def createScene(rootNode):
    body = rootNode.addChild("body")
    body.addObject("MechanicalObjekt", name="dofs")
